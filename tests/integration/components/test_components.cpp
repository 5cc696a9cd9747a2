// Components used by the integration tests: a counter source, a summing sink, a component that
// crashes on demand, a service provider and caller, and an event pair. Built as a real
// component library (keel_add_component) and loaded through profiles, as users do.
#include <keel/component.hpp>

#include <stdexcept>

namespace itest {

class Counter : public keel::Component {
 public:
  keel::OutputDataPort<int> count{this, "count"};
  keel::ReturnCode onInitialize() override {
    step_ = property<int>("step", 1);
    critical(n_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    n_ += step_;
    count.push(n_);
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
  int step_ = 1;
};

class Summer : public keel::Component {
 public:
  keel::InputDataPort<int> in{this, "in"};
  keel::OutputEventPort<keel::Event> milestones{this, "milestones"};
  keel::ReturnCode onInitialize() override {
    gain_ = property<double>("gain");
    label_ = property<std::string>("label", "summer");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    while (auto v = in.pop()) {
      sum_ += gain_ * *v;
      if (++received_ % 10 == 0) milestones.send(keel::Event{label_, received_, sum_});
    }
    return keel::ReturnCode::Ok;
  }

 private:
  double gain_ = 1.0;
  std::string label_;
  long received_ = 0;
  double sum_ = 0;
};

class EventLogger : public keel::Component {
 public:
  keel::InputEventPort<keel::Event> events{this, "events"};
  keel::ReturnCode onEvent(keel::InputEventPortBase& port) override {
    if (&port == &events && events.current().code >= 30) raiseFault("milestone 30 reached: " + events.current().name);
    return keel::ReturnCode::Ok;
  }
};

class Crasher : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    at_ = property<int>("crash_at");
    mode_ = property<std::string>("mode", "segfault");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    if (++n_ != at_) return keel::ReturnCode::Ok;
    if (mode_ == "throw") throw std::runtime_error("crasher gave up");
    if (mode_ == "error_code") return keel::ReturnCode::InternalFault;
    volatile std::uintptr_t addr = 0x10;
    *reinterpret_cast<volatile int*>(addr) = 1;
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
  int at_ = 0;
  std::string mode_;
};

class Doubler : public keel::Component {
 public:
  keel::ProvidedServicePort<int(int)> twice{this, "twice", [](int x) { return 2 * x; }};
};

class Caller : public keel::Component {
 public:
  keel::RequiredServicePort<int(int)> twice{this, "twice"};
  keel::OutputDataPort<int> answers{this, "answers"};
  keel::ReturnCode onExecute() override {
    auto r = twice.call(++n_);
    if (!r) return keel::ReturnCode::CallApiError;
    answers.push(*r);
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Counter, "Counter")
KEEL_REGISTER_COMPONENT_AS(itest::Summer, "Summer")
KEEL_REGISTER_COMPONENT_AS(itest::EventLogger, "EventLogger")
KEEL_REGISTER_COMPONENT_AS(itest::Crasher, "Crasher")
KEEL_REGISTER_COMPONENT_AS(itest::Doubler, "Doubler")
KEEL_REGISTER_COMPONENT_AS(itest::Caller, "Caller")
