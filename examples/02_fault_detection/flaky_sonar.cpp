// A sonar driver with a bug: on its Nth reading it dereferences a bad pointer (or throws, or
// returns an error code, by the `fault` property). keel catches the fault around onExecute,
// moves this component to Error and keeps every other component running.
#include <keel/component.hpp>

#include <cmath>
#include <cstdint>
#include <stdexcept>

class FlakySonar : public keel::Component {
 public:
  keel::OutputDataPort<double> distance{this, "distance"};

  keel::ReturnCode onInitialize() override {
    fail_at_ = property<int>("fail_at");
    fault_ = property<std::string>("fault");
    return keel::ReturnCode::Ok;
  }

  keel::ReturnCode onExecute() override {
    ++reading_;
    if (reading_ == fail_at_) {
      if (fault_ == "segfault") {
        volatile std::uintptr_t bad = 0x10;         // a driver bug: a dangling pointer
        *reinterpret_cast<volatile int*>(bad) = 0;  // NOLINT(performance-no-int-to-ptr): the bug shown
      }
      if (fault_ == "throw") throw std::runtime_error("serial port read failed");
      if (fault_ == "error_code") return keel::ReturnCode::InternalFault;
    }
    distance.push(150.0 + 50.0 * std::sin(reading_ / 10.0));  // cm
    return keel::ReturnCode::Ok;
  }

 private:
  int reading_ = 0;
  int fail_at_ = 0;
  std::string fault_;
};

KEEL_REGISTER_COMPONENT(FlakySonar)
