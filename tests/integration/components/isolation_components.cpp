// Components for the process-isolation tests (tests/integration/isolation_test.cpp): a producer of
// self-checking samples, a consumer that counts torn, lost and reordered ones, a component that
// dies the way a real process does (outside keel's guard), one that hangs past keel's interrupt,
// and an actuator that writes down its emergency stop.
#include <keel/component.hpp>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

namespace itest {

/// 64 bytes that say whether they arrived whole: every word is derived from `seq`.
struct Pattern {
  std::uint64_t seq = 0;
  std::array<std::uint64_t, 7> words{};
};

inline std::uint64_t wordOf(std::uint64_t seq, std::size_t i) { return (seq * 0x9E3779B97F4A7C15ULL) ^ (i + 1); }

/// Pushes Pattern 1, 2, 3, ... every period; `seq` is its critical memory.
class PatternSource : public keel::Component {
 public:
  keel::OutputDataPort<Pattern> out{this, "out"};
  keel::ReturnCode onInitialize() override {
    critical(seq_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    Pattern p;
    p.seq = ++seq_;
    for (std::size_t i = 0; i < p.words.size(); ++i) p.words[i] = wordOf(p.seq, i);
    out.push(p);
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t seq_ = 0;
};

/// Checks every Pattern: torn (a word that does not match its seq), a gap (seq jumped ahead),
/// back (seq not above the last: a restart from a checkpoint) and how far back at most (a restart
/// from a checkpoint falls by a sample or two, one from scratch by the whole count). Writes its
/// counts to the file `report` when it stops: "received gaps back torn last max_back".
class PatternCheck : public keel::Component {
 public:
  keel::InputDataPort<Pattern> in{this, "in"};
  keel::ReturnCode onInitialize() override {
    report_ = property<std::string>("report", "");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    take();
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStop() override {
    take();  // a passive checker takes everything here: nothing runs it before
    if (!report_.empty())
      std::ofstream(report_) << received_ << ' ' << gaps_ << ' ' << back_ << ' ' << torn_ << ' ' << last_ << ' '
                             << max_back_ << '\n';
    return keel::ReturnCode::Ok;
  }

 private:
  void take() {
    while (auto p = in.pop()) {
      ++received_;
      for (std::size_t i = 0; i < p->words.size(); ++i)
        if (p->words[i] != wordOf(p->seq, i)) {
          ++torn_;
          break;
        }
      if (last_ != 0 && p->seq > last_ + 1) ++gaps_;
      if (last_ != 0 && p->seq <= last_) {
        ++back_;
        max_back_ = std::max(max_back_, last_ - p->seq + 1);
      }
      last_ = p->seq;
    }
  }
  std::string report_;
  std::uint64_t received_ = 0, gaps_ = 0, back_ = 0, torn_ = 0, last_ = 0, max_back_ = 0;
};

/// Dies as a process does, from a thread of its own (outside the guard), `after_ms` after it
/// starts: `how` is segfault, abort, exit (status 3) or stop (SIGSTOP: hangs whole).
class Doomed : public keel::Component {
 public:
  keel::OutputDataPort<Pattern> out{this, "out"};
  keel::ReturnCode onInitialize() override {
    how_ = property<std::string>("how", "exit");
    after_ms_ = property<int>("after_ms", 100);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStart() override {
    std::thread([how = how_, after = after_ms_] {
      std::this_thread::sleep_for(std::chrono::milliseconds(after));
      if (how == "segfault") {  // page 0 is never mapped; not null, which UBSan would stop first
        volatile std::uintptr_t addr = 0x10;
        *reinterpret_cast<volatile int*>(addr) = 1;  // NOLINT(performance-no-int-to-ptr): the point
      }
      if (how == "abort") std::abort();
      if (how == "stop") ::raise(SIGSTOP);
      std::_Exit(3);
    }).detach();
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    Pattern p;
    p.seq = ++seq_;
    out.push(p);
    return keel::ReturnCode::Ok;
  }

 private:
  std::string how_;
  int after_ms_ = 100;
  std::uint64_t seq_ = 0;
};

/// Hangs in one onExecute, `after_ms` after it starts, for `hang_ms`, with every signal blocked
/// (as a badly behaved library might): keel's interrupt cannot end the callback, so its executor
/// is abandoned, and the thread comes back when the hang ends.
class Stubborn : public keel::Component {
 public:
  keel::OutputDataPort<Pattern> out{this, "out"};
  keel::ReturnCode onInitialize() override {
    after_ms_ = property<int>("after_ms", 500);
    hang_ms_ = property<int>("hang_ms", 300);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStart() override {
    hang_at_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(after_ms_);
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    Pattern p;
    p.seq = ++seq_;
    out.push(p);
    if (!hung_ && std::chrono::steady_clock::now() >= hang_at_) {
      hung_ = true;
      sigset_t all, old;
      sigfillset(&all);
      pthread_sigmask(SIG_BLOCK, &all, &old);
      std::this_thread::sleep_for(std::chrono::milliseconds(hang_ms_));
      pthread_sigmask(SIG_SETMASK, &old, nullptr);
    }
    return keel::ReturnCode::Ok;
  }

 private:
  int after_ms_ = 500;
  int hang_ms_ = 300;
  std::chrono::steady_clock::time_point hang_at_{};
  bool hung_ = false;
  std::uint64_t seq_ = 0;
};

/// An actuator that appends "emergency <pid>" to the file `trace` in its onEmergencyStop.
class Brake : public keel::Component {
 public:
  keel::InputDataPort<Pattern> in{this, "in"};
  keel::ReturnCode onInitialize() override {
    trace_ = property<std::string>("trace", "");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    while (in.pop()) {}
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onEmergencyStop() override {
    if (!trace_.empty()) std::ofstream(trace_, std::ios::app) << "emergency " << ::getpid() << std::endl;
    return keel::ReturnCode::Ok;
  }

 private:
  std::string trace_;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::PatternSource, "PatternSource")
KEEL_REGISTER_COMPONENT_AS(itest::PatternCheck, "PatternCheck")
KEEL_REGISTER_COMPONENT_AS(itest::PatternCheck, "PatternCheckPassive")
KEEL_REGISTER_COMPONENT_AS(itest::Doomed, "Doomed")
KEEL_REGISTER_COMPONENT_AS(itest::Stubborn, "Stubborn")
KEEL_REGISTER_COMPONENT_AS(itest::Brake, "Brake")
