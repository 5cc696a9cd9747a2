// Components for the tests of the runtime's hooks for a robot run: a Finisher that ends the run
// (RunControl::endRun) after a number of executions or from its onStop, and a Driver that gets
// the scenario's hardware faults (keel::HardwareDriver::onHardwareFault). Built into the test component
// library with the others.
#include <keel/component.hpp>
#include <keel/hardware_driver.hpp>
#include <keel/run_control.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>

namespace itest {

/// Ends the run after `end_after` executions (0: never), or from onStop with `end_on_stop`.
/// The end's record is `event` with the members `fields` and "executions":N (when `fields` is
/// not empty). A second call right after the first shows that only the first counts.
class Finisher : public keel::Component, public keel::RunControl {
 public:
  keel::ReturnCode onInitialize() override {
    end_after_ = property<int>("end_after", 0);
    end_on_stop_ = property<bool>("end_on_stop", false);
    event_ = property<std::string>("event", "");
    fields_ = property<std::string>("fields", "");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    if (++n_ != end_after_) return keel::ReturnCode::Ok;
    endRun("done after " + std::to_string(n_) + " executions", event_, fields());
    endRun("a second call", "ignored", "\"ignored\":true");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStop() override {
    if (end_on_stop_) endRun("stopped after " + std::to_string(n_) + " executions", event_, fields());
    return keel::ReturnCode::Ok;
  }

 private:
  std::string fields() const { return fields_.empty() ? fields_ : fields_ + ",\"executions\":" + std::to_string(n_); }
  int n_ = 0;
  int end_after_ = 0;
  bool end_on_stop_ = false;
  std::string event_;
  std::string fields_;
};

/// A simulated hardware driver: prints every hardware fault it is given, with the ms since its
/// onStart ("[driver] hardware fault 'motor_power_off left' at 101 ms"). It cannot apply
/// `noise` (BadInput), and its board is unreachable for args "explode" (throws).
class Driver : public keel::Component, public keel::HardwareDriver {
 public:
  keel::ReturnCode onStart() override {
    start_ns_.store(nowNs(), std::memory_order_release);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onHardwareFault(std::string_view command) override {  // the injector's thread
    const double ms = static_cast<double>(nowNs() - start_ns_.load(std::memory_order_acquire)) / 1e6;
    {
      std::lock_guard lock(mutex_);
      std::printf("[%s] hardware fault '%.*s' at %.0f ms\n", instanceName().c_str(), static_cast<int>(command.size()),
                  command.data(), ms);
      std::fflush(stdout);
    }
    if (command.find("explode") != std::string_view::npos) throw std::runtime_error("board unreachable");
    if (command.rfind("noise", 0) == 0) return keel::ReturnCode::BadInput;
    return keel::ReturnCode::Ok;
  }

 private:
  static std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  std::atomic<std::int64_t> start_ns_{0};
  std::mutex mutex_;
};

/// Appends `prefix` and `callback`'s name as a line to the file `trace` (a test reads the
/// callbacks keel called, in order); Ok.
static keel::ReturnCode traceCallback(const std::string& trace, const char* prefix, const char* callback) {
  if (std::FILE* f = std::fopen(trace.c_str(), "a")) {
    std::fprintf(f, "%s%s\n", prefix, callback);
    std::fclose(f);
  }
  return keel::ReturnCode::Ok;
}

/// Writes the name of each lifecycle and recovery callback keel calls to the file `trace`, and
/// fails its onInitialize when `refuse` is set, as a driver whose device is missing does. Its
/// onStop then dereferences what onInitialize never set up, as such a driver would. With
/// `fail_stop` its onStop throws, as a driver whose stop command is not acknowledged. With
/// `throw_at` N its Nth onExecute throws (once).
class Refuser : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    trace_ = property<std::string>("trace");
    note("onInitialize");
    if (property<bool>("refuse", false)) throw std::runtime_error("no device at /dev/nothing");
    device_ = &opened_;
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStart() override { return note("onStart"); }
  keel::ReturnCode onExecute() override {
    if (++executions_ == property<int>("throw_at", 0)) throw std::runtime_error("a bad reading");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStop() override {
    note("onStop");
    *device_ = 0;  // a null pointer unless onInitialize succeeded
    if (property<bool>("fail_stop", false)) throw std::runtime_error("stop command not acknowledged");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onDestroy() override { return note("onDestroy"); }
  keel::ReturnCode onEmergencyStop() override { return note("onEmergencyStop"); }
  keel::ReturnCode onError() override { return note("onError"); }
  keel::ReturnCode onReset() override { return note("onReset"); }
  keel::ReturnCode onRecover() override { return note("onRecover"); }

 private:
  keel::ReturnCode note(const char* callback) const { return traceCallback(trace_, "", callback); }
  std::string trace_;
  int opened_ = 0;
  int* device_ = nullptr;
  int executions_ = 0;
};

/// An alternative whose device is missing: its onInitialize throws. Writes "Unplugged." and the
/// callback's name to the file `trace`.
class Unplugged : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    trace_ = property<std::string>("trace");
    note("onInitialize");
    throw std::runtime_error("no device at /dev/spare");
  }
  keel::ReturnCode onStart() override { return note("onStart"); }
  keel::ReturnCode onStop() override { return note("onStop"); }
  keel::ReturnCode onDestroy() override { return note("onDestroy"); }

 private:
  keel::ReturnCode note(const char* callback) const { return traceCallback(trace_, "Unplugged.", callback); }
  std::string trace_;
};

/// A component whose constructor throws, as one that reads a missing calibration file there.
class Fragile : public keel::Component {
 public:
  Fragile() { throw std::runtime_error("no calibration file at /etc/fragile.yaml"); }
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Finisher, "Finisher")
KEEL_REGISTER_COMPONENT_AS(itest::Fragile, "Fragile")
KEEL_REGISTER_COMPONENT_AS(itest::Unplugged, "Unplugged")
KEEL_REGISTER_COMPONENT_AS(itest::Refuser, "Refuser")
KEEL_REGISTER_COMPONENT_AS(itest::Driver, "Driver")
