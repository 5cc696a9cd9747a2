// Components used by the integration tests: a counter source, a summing sink, a component that
// crashes on demand, a service provider and caller, and an event pair. Built as a real
// component library (keel_add_component) and loaded through profiles, as users do.
#include <keel/component.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>
#include <vector>

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
    *reinterpret_cast<volatile int*>(addr) = 1;  // NOLINT(performance-no-int-to-ptr): the crash it exists for
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

/// Works `work_ms`, then calls: at a run's end its last cycle is still working when the others
/// have ended theirs.
class SlowCaller : public keel::Component {
 public:
  keel::RequiredServicePort<int(int)> twice{this, "twice"};
  keel::ReturnCode onInitialize() override {
    work_ms_ = property<double>("work_ms");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(work_ms_));
    return twice.call(++n_) ? keel::ReturnCode::Ok : keel::ReturnCode::CallApiError;
  }

 private:
  double work_ms_ = 0;
  int n_ = 0;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Counter, "Counter")
KEEL_REGISTER_COMPONENT_AS(itest::Summer, "Summer")
KEEL_REGISTER_COMPONENT_AS(itest::EventLogger, "EventLogger")
KEEL_REGISTER_COMPONENT_AS(itest::Crasher, "Crasher")
KEEL_REGISTER_COMPONENT_AS(itest::Doubler, "Doubler")
KEEL_REGISTER_COMPONENT_AS(itest::Caller, "Caller")
KEEL_REGISTER_COMPONENT_AS(itest::SlowCaller, "SlowCaller")

namespace itest {

/// A smooth signal in [-1, 1], as a number and as an array of three.
class Wave : public keel::Component {
 public:
  keel::OutputDataPort<double> value{this, "value"};
  keel::OutputDataPort<std::vector<double>> values{this, "values"};
  keel::ReturnCode onExecute() override {
    const double x = std::sin(++n_ / 10.0);
    value.push(x);
    values.push({x, x / 2, -x});
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

/// Receives a number and an array, counts what arrived.
class Probe : public keel::Component {
 public:
  keel::InputDataPort<double> in{this, "in"};
  keel::InputDataPort<std::vector<double>> arr{this, "arr"};
  keel::ReturnCode onExecute() override {
    while (in.pop()) ++received_;
    while (arr.pop()) ++received_;
    return keel::ReturnCode::Ok;
  }

 private:
  long received_ = 0;
};

/// Sleeps `sleep_ms` every `every` cycles: a real deadline overrun.
class Sleepy : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    every_ = property<int>("every");
    sleep_ms_ = property<double>("sleep_ms");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    if (++n_ % every_ == 0) std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(sleep_ms_ * 1000)));
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
  int every_ = 1;
  double sleep_ms_ = 0;
};

/// Tells the fault manager, through its `faults` port, that another component is faulty.
class Tattler : public keel::Component {
 public:
  keel::OutputEventPort<keel::FaultEvent> faults{this, "faults"};
  keel::ReturnCode onInitialize() override {
    about_ = property<std::string>("about");
    at_ = property<int>("at");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    if (++n_ == at_) faults.send(keel::FaultEvent(keel::FaultKind::Model, about_, "tattler saw drift"));
    return keel::ReturnCode::Ok;
  }

 private:
  std::string about_;
  int at_ = 0;
  int n_ = 0;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Wave, "Wave")
KEEL_REGISTER_COMPONENT_AS(itest::Probe, "Probe")
KEEL_REGISTER_COMPONENT_AS(itest::Sleepy, "Sleepy")
KEEL_REGISTER_COMPONENT_AS(itest::Tattler, "Tattler")

namespace itest {

/// A constant level that drops to `drop_to` after `drop_at` executions (a wheel losing power),
/// and a little deterministic ripple so that a filter has work to do.
class Level : public keel::Component {
 public:
  keel::OutputDataPort<double> value{this, "value"};
  keel::ReturnCode onInitialize() override {
    level_ = property<double>("level");
    drop_at_ = property<int>("drop_at");
    drop_to_ = property<double>("drop_to");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    ++n_;
    const double base = (drop_at_ > 0 && n_ >= drop_at_) ? drop_to_ : level_;
    value.push(base + ((n_ % 2) ? 1.0 : -1.0));
    return keel::ReturnCode::Ok;
  }

 private:
  double level_ = 0, drop_to_ = 0;
  int drop_at_ = 0, n_ = 0;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Level, "Level")
