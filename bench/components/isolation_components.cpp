// Components of `keel bench isolation` (bench/harness/isolation.cpp). Each maps the harness's
// page (bench_page.hpp), named by its `page` property, and writes there what the harness
// measures:
//   BenchBeat         a periodic step with 4 KB of critical memory (checkpointed, restored by a
//                     takeover or respawn): the end of the first step a new process runs is the
//                     takeover's end
//   BenchStampSource  pushes {seq, CLOCK_MONOTONIC} every period, the time taken right before
//                     the push
//   BenchStampSink    aperiodic, woken by each sample: arrival − stamp, the port's one-way latency
#include <unistd.h>

#include <keel/component.hpp>

#include <array>
#include <cstdint>
#include <string>

#include "bench_page.hpp"

namespace keel_bench {
namespace {

class BenchBeat : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    page_ = mapPage(property<std::string>("page", ""));
    if (page_ == nullptr) return keel::ReturnCode::PreconditionNotMet;
    critical(state_);
    const auto k = page_->initialised.fetch_add(1);
    if (k < BenchPage::kMaxPids) page_->pids[k].store(::getpid());
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    ++state_[steps_++ % state_.size()];
    page_->executions.fetch_add(1, std::memory_order_relaxed);
    if (!running_here_) {
      running_here_ = true;
      page_->first_ns.store(monotonicNs(), std::memory_order_relaxed);
      page_->active_pid.store(::getpid(), std::memory_order_release);
    }
    return keel::ReturnCode::Ok;
  }

 private:
  BenchPage* page_ = nullptr;
  std::array<std::uint8_t, 4096> state_{};
  std::uint64_t steps_ = 0;
  bool running_here_ = false;
};

class BenchStampSource : public keel::Component {
 public:
  keel::OutputDataPort<Stamp> out{this, "out"};
  keel::ReturnCode onExecute() override {
    Stamp s;
    s.seq = ++seq_;
    s.t_ns = monotonicNs();
    out.push(s);
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t seq_ = 0;
};

class BenchStampSink : public keel::Component {
 public:
  keel::InputDataPort<Stamp> in{this, "in"};
  keel::ReturnCode onInitialize() override {
    page_ = mapPage(property<std::string>("page", ""));
    return page_ != nullptr ? keel::ReturnCode::Ok : keel::ReturnCode::PreconditionNotMet;
  }
  keel::ReturnCode onExecute() override {
    const std::int64_t now = monotonicNs();
    while (auto s = in.pop()) {
      const auto k = page_->received.fetch_add(1, std::memory_order_relaxed);
      if (k < BenchPage::kMaxSamples) page_->latency_ns[k].store(now - s->t_ns, std::memory_order_relaxed);
    }
    return keel::ReturnCode::Ok;
  }

 private:
  BenchPage* page_ = nullptr;
};

}  // namespace
}  // namespace keel_bench

KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchBeat, "BenchBeat")
KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchStampSource, "BenchStampSource")
KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchStampSink, "BenchStampSink")
