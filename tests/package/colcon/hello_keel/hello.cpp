// Talker counts its cycles on `said`; Listener adds up what it hears and reports a fault of its
// own if it hears nothing, so that a run's log shows the connection works.
#include <keel/component.hpp>

#include <optional>

class Talker : public keel::Component {
 public:
  keel::OutputDataPort<int> said{this, "said"};

  keel::ReturnCode onExecute() override {
    said.push(++cycles_);
    return keel::ReturnCode::Ok;
  }

 private:
  int cycles_ = 0;
};
KEEL_REGISTER_COMPONENT(Talker)

class Listener : public keel::Component {
 public:
  keel::InputDataPort<int> heard{this, "heard"};

  keel::ReturnCode onExecute() override {
    while (std::optional<int> n = heard.pop()) heard_ += *n;
    if (++cycles_ == 50 && heard_ == 0) raiseFault("heard nothing");
    return keel::ReturnCode::Ok;
  }

 private:
  long heard_ = 0;
  int cycles_ = 0;
};
KEEL_REGISTER_COMPONENT(Listener)
