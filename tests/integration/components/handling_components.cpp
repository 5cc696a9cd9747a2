// Components for the fault-handling scenario tests (tests/scenarios/handling_test.cpp): a
// checkpointed tally and its alternative class, a tap that watches what a tally publishes, an
// actuator that goes to neutral on an emergency stop and a motor that receives its commands,
// and a twin whose critical memory is a block of equal words (a torn copy would show).
// Each reports what it saw through a probe (a name → value table in this library) that the
// test reads with dlsym("keel_handling_probe"): the values a component published, restored or
// received are asserted directly, not guessed from the log.
#include <keel/component.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

namespace htest {
namespace {

std::mutex g_probe_mutex;
std::map<std::string, long>& probes() {
  static std::map<std::string, long> p;
  return p;
}

void set(const keel::Component& c, const std::string& key, long v) {
  std::lock_guard lock(g_probe_mutex);
  probes()[c.instanceName() + "/" + key] = v;
}
void add(const keel::Component& c, const std::string& key, long v = 1) {
  std::lock_guard lock(g_probe_mutex);
  probes()[c.instanceName() + "/" + key] += v;
}

/// Counts callbacks of one component that overlap (keel promises there are none).
class Overlap {
 public:
  struct Scope {
    Scope(Overlap& o, const keel::Component& c) : o_(o) {
      if (o_.inside_.exchange(true, std::memory_order_acq_rel)) add(c, "overlaps");
    }
    ~Scope() { o_.inside_.store(false, std::memory_order_release); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    Overlap& o_;
  };

 private:
  std::atomic<bool> inside_{false};
};

}  // namespace

/// Counts up by one every cycle and publishes the count; the count is critical memory.
/// Probe: n (latest), at_error (n when onError ran), restored (n in onRecover, i.e. after the
/// checkpoint was restored), errors, resets, recovers.
class Tally : public keel::Component {
 public:
  keel::OutputDataPort<int> count{this, "count"};
  keel::ReturnCode onInitialize() override {
    critical(n_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    count.push(++n_);
    set(*this, "n", n_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onError() override {
    set(*this, "at_error", n_);
    add(*this, "errors");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onReset() override {
    add(*this, "resets");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onRecover() override {
    set(*this, "restored", n_);
    add(*this, "recovers");
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

/// Tally's alternative: the same port and the same critical memory layout. Probe keys are
/// prefixed "backup." (it runs under the instance name of the tally it replaces).
class TallyBackup : public keel::Component {
 public:
  keel::OutputDataPort<int> count{this, "count"};
  keel::ReturnCode onInitialize() override {
    critical(n_);
    add(*this, "backup.initialized");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStart() override {
    set(*this, "backup.start_n", n_);  // the checkpointed state it took over
    add(*this, "backup.starts");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    count.push(++n_);
    set(*this, "backup.n", n_);
    add(*this, "backup.executions");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onError() override {
    add(*this, "backup.errors");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onRecover() override {
    add(*this, "backup.recovers");
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

/// Receives a tally's counts. Probe: received, last, max_drop (largest fall between two
/// consecutive values: a rewind to the checkpoint, or a restart from 0).
class Tap : public keel::Component {
 public:
  keel::InputDataPort<int> in{this, "in"};
  keel::ReturnCode onExecute() override {
    while (auto v = in.pop()) {
      if (received_ > 0 && *v < last_) max_drop_ = std::max<long>(max_drop_, last_ - *v);
      last_ = *v;
      ++received_;
    }
    set(*this, "received", received_);
    set(*this, "last", last_);
    set(*this, "max_drop", max_drop_);
    return keel::ReturnCode::Ok;
  }

 private:
  long received_ = 0;
  int last_ = 0;
  long max_drop_ = 0;
};

/// An actuator: commands a speed in [1, 2) every cycle; on an emergency stop it commands 0
/// ("stop in neutral") and keeps commanding 0 while the emergency is latched.
/// Probe: cmd_milli (latest command × 1000), estops, overlaps, executions_latched.
class Actuator : public keel::Component {
 public:
  keel::OutputDataPort<double> command{this, "command"};
  keel::ReturnCode onExecute() override {
    Overlap::Scope s(overlap_, *this);
    if (emergencyLatched()) {
      cmd_ = 0.0;
      add(*this, "executions_latched");
    } else {
      cmd_ = 1.0 + static_cast<double>(++n_ % 10) / 10.0;
    }
    command.push(cmd_);
    set(*this, "cmd_milli", static_cast<long>(cmd_ * 1000));
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onEmergencyStop() override {
    Overlap::Scope s(overlap_, *this);
    cmd_ = 0.0;
    command.push(cmd_);
    set(*this, "cmd_milli", 0);
    add(*this, "estops");
    return keel::ReturnCode::Ok;
  }

 private:
  Overlap overlap_;
  double cmd_ = 0.0;
  int n_ = 0;
};

/// Receives an actuator's commands. Probe: last_milli, received.
class Motor : public keel::Component {
 public:
  keel::InputDataPort<double> in{this, "in"};
  keel::ReturnCode onExecute() override {
    while (auto v = in.pop()) {
      set(*this, "last_milli", static_cast<long>(*v * 1000));
      add(*this, "received");
    }
    return keel::ReturnCode::Ok;
  }
};

/// Critical memory of 32 words kept equal: every cycle each is incremented in turn, so a copy
/// taken or restored in the middle of a cycle would not be equal. Probe: executions, recovers,
/// torn (a start, restore or cycle that found unequal words), restored, at_error, min_lost and
/// max_lost (over its resets, the counts between the fault and the restored state), starts,
/// start_value, overlaps.
class Twin : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    critical(block_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStart() override {
    Overlap::Scope s(overlap_, *this);
    add(*this, "starts");
    if (!equal()) add(*this, "torn");
    set(*this, "start_value", static_cast<long>(block_.w[0]));
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    Overlap::Scope s(overlap_, *this);
    if (!equal()) add(*this, "torn");
    for (auto& w : block_.w) w = w + 1;
    set(*this, "value", static_cast<long>(block_.w[0]));
    add(*this, "executions");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onError() override {
    Overlap::Scope s(overlap_, *this);
    at_error_ = block_.w[0];
    set(*this, "at_error", static_cast<long>(at_error_));
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onRecover() override {
    Overlap::Scope s(overlap_, *this);
    add(*this, "recovers");
    set(*this, "restored", static_cast<long>(block_.w[0]));
    const long lost = static_cast<long>(at_error_) - static_cast<long>(block_.w[0]);
    min_lost_ = std::min(min_lost_, lost);
    max_lost_ = std::max(max_lost_, lost);
    set(*this, "min_lost", min_lost_);
    set(*this, "max_lost", max_lost_);
    if (!equal()) {
      add(*this, "torn");
      return keel::ReturnCode::InternalFault;
    }
    return keel::ReturnCode::Ok;
  }

 private:
  struct Block {
    std::uint64_t w[32];
  };
  bool equal() const {
    for (auto w : block_.w)
      if (w != block_.w[0]) return false;
    return true;
  }
  Overlap overlap_;
  Block block_{};
  std::uint64_t at_error_ = 0;
  long min_lost_ = 1L << 40, max_lost_ = -(1L << 40);
};

}  // namespace htest

namespace htest {

/// A passive tally: each call of its service `next` adds `step` to the count (critical memory)
/// and returns it; at the count `fail_at` (once) the call throws. Probe: at_error, restored, as
/// Tally's.
class PassiveTally : public keel::Component {
 public:
  keel::ProvidedServicePort<int(int)> next{this, "next", [this](int step) { return add(step); }};
  keel::ReturnCode onInitialize() override {
    critical(n_);
    fail_at_ = property<int>("fail_at", 0);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onError() override {
    set(*this, "at_error", n_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onRecover() override {
    set(*this, "restored", n_);
    return keel::ReturnCode::Ok;
  }

 private:
  int add(int step) {
    n_ += step;
    if (n_ == fail_at_ && !failed_) {
      failed_ = true;  // not critical: once per run
      throw std::runtime_error("tally corrupted");
    }
    return n_;
  }
  int n_ = 0;
  int fail_at_ = 0;
  bool failed_ = false;
};

/// Calls `next(1)` every cycle; probe: last (the latest answer) and max_drop (the largest fall
/// between two answers).
class TallyClient : public keel::Component {
 public:
  keel::RequiredServicePort<int(int)> next{this, "next"};
  keel::ReturnCode onExecute() override {
    auto r = next.call(1);
    if (!r) return keel::ReturnCode::Ok;  // the failed call: the tally's fault, not ours
    if (last_ - *r > max_drop_) set(*this, "max_drop", max_drop_ = last_ - *r);
    set(*this, "last", last_ = *r);
    return keel::ReturnCode::Ok;
  }

 private:
  int last_ = 0;
  int max_drop_ = 0;
};

}  // namespace htest

/// The probe, read by the test through dlsym: 1 and the value in *out when `instance/key` was
/// set, 0 otherwise.
extern "C" int keel_handling_probe(const char* instance, const char* key, long* out) {
  std::lock_guard lock(htest::g_probe_mutex);
  auto it = htest::probes().find(std::string(instance) + "/" + key);
  if (it == htest::probes().end()) return 0;
  *out = it->second;
  return 1;
}

/// Forgets every probe (each test starts from an empty table).
extern "C" void keel_handling_probe_clear() {
  std::lock_guard lock(htest::g_probe_mutex);
  htest::probes().clear();
}

KEEL_REGISTER_COMPONENT_AS(htest::Tally, "Tally")
KEEL_REGISTER_COMPONENT_AS(htest::TallyBackup, "TallyBackup")
KEEL_REGISTER_COMPONENT_AS(htest::Tap, "Tap")
KEEL_REGISTER_COMPONENT_AS(htest::PassiveTally, "PassiveTally")
KEEL_REGISTER_COMPONENT_AS(htest::TallyClient, "TallyClient")
KEEL_REGISTER_COMPONENT_AS(htest::Actuator, "Actuator")
KEEL_REGISTER_COMPONENT_AS(htest::Motor, "Motor")
KEEL_REGISTER_COMPONENT_AS(htest::Twin, "Twin")
