// Announcer: a periodic component whose port carries a ROS 2 message type of the project's own
// (greeters_msgs/msg/Greeting, built by keel_add_messages from greeters_msgs/msg/*.msg).
#include <keel/component.hpp>
#include <keel/msg/greeters_msgs/msg/greeting.hpp>
#include <keel/msg/std_msgs/msg/float64.hpp>

class Announcer : public keel::Component {
 public:
  keel::OutputDataPort<keel::msg::greeters_msgs::Greeting> greeting{this, "greeting"};
  keel::InputDataPort<keel::msg::std_msgs::Float64> volume{this, "volume"};

  keel::ReturnCode onExecute() override {
    keel::msg::greeters_msgs::Greeting g;
    g.header.frame_id = "announcer";
    g.text = "hello";
    g.count = ++count_;
    greeting.push(g);
    return keel::ReturnCode::Ok;
  }

 private:
  unsigned count_ = 0;
};
KEEL_REGISTER_COMPONENT(Announcer)
