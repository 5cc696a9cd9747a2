// An aperiodic component: runs when a count arrives; prints milestones it receives as events.
#include <keel/component.hpp>

#include <cstdio>

class Listener : public keel::Component {
 public:
  keel::InputDataPort<int> count{this, "count"};
  keel::InputEventPort<keel::Event> news{this, "news"};

  keel::ReturnCode onExecute() override {
    while (auto v = count.pop()) last_ = *v;
    return keel::ReturnCode::Ok;
  }

  keel::ReturnCode onEvent(keel::InputEventPortBase& port) override {
    if (&port == &news)
      std::printf("[%s] %s: %ld (last count seen: %d)\n", instanceName().c_str(), news.current().name.c_str(),
                  static_cast<long>(news.current().code), last_);
    return keel::ReturnCode::Ok;
  }

 private:
  int last_ = 0;
};

KEEL_REGISTER_COMPONENT(Listener)
