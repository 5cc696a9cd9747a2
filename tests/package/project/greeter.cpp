// Greeter: a periodic component that sends a numbered greeting to its `greeting` port each
// cycle. Its greeting text is the profile's `text` property; the number of greetings sent is
// checkpointed with critical().
#include <keel/component.hpp>

#include <string>

class Greeter : public keel::Component {
 public:
  keel::OutputDataPort<std::string> greeting{this, "greeting"};

  keel::ReturnCode onInitialize() override {
    text_ = property<std::string>("text");
    critical(&sent_, sizeof sent_);
    return keel::ReturnCode::Ok;
  }

  keel::ReturnCode onExecute() override {
    ++sent_;
    greeting.push(text_ + " #" + std::to_string(sent_));
    return keel::ReturnCode::Ok;
  }

 private:
  std::string text_;
  long sent_ = 0;
};
KEEL_REGISTER_COMPONENT(Greeter)
