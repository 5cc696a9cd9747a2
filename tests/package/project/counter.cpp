// Counter: counts the greetings arriving on `greetings` and publishes the total on `count`.
// The total is checkpointed with critical(). If nothing has arrived after kPatience cycles the
// connection is broken, and Counter reports it as its own fault (kind `user`), which the
// package test sees in the fault log.
#include <keel/component.hpp>

#include <optional>
#include <string>

class Counter : public keel::Component {
 public:
  keel::InputDataPort<std::string> greetings{this, "greetings"};
  keel::OutputDataPort<int> count{this, "count"};

  keel::ReturnCode onInitialize() override {
    critical(count_);
    return keel::ReturnCode::Ok;
  }

  keel::ReturnCode onExecute() override {
    while (std::optional<std::string> g = greetings.pop()) {
      if (g->empty()) return keel::ReturnCode::BadInput;
      ++count_;
    }
    count.push(count_);
    if (++cycles_ == kPatience && count_ == 0) raiseFault("no greeting arrived");
    return keel::ReturnCode::Ok;
  }

 private:
  static constexpr int kPatience = 50;
  int count_ = 0;
  int cycles_ = 0;
};
KEEL_REGISTER_COMPONENT(Counter)
