// Components of `keel bench dds` (bench/harness/dds.cpp). Their ports carry ROS 2's
// std_msgs/msg/Header, bound to DDS topics by the profiles the harness writes; the stamp is the
// sender's CLOCK_MONOTONIC (one machine: every process reads the same clock), the frame_id the
// writer's `who`. The sink maps the harness's page (bench_page.hpp) and writes there what it sees:
//   BenchDdsStamp  periodic: {stamp: now, frame_id: who} every period, the time taken right
//                  before the push
//   BenchDdsEcho   aperiodic, woken by each sample: pushes it back out as it came
//   BenchDdsSink   aperiodic, woken by each sample: arrival − stamp (for a stamp that went out
//                  and came back through an echo, the round trip); and, when the sample's writer
//                  is not the last one's, that writer and the arrival (a failover's end)
#include <keel/component.hpp>
#include <keel/msg/std_msgs/msg/header.hpp>

#include <charconv>
#include <cstdint>
#include <string>

#include "bench_page.hpp"

namespace keel_bench {
namespace {

using keel::msg::std_msgs::Header;

class BenchDdsStamp : public keel::Component {
 public:
  keel::OutputDataPort<Header> out{this, "out"};
  keel::ReturnCode onInitialize() override {
    who_ = std::to_string(property<int>("who", 1));
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    Header h;
    h.frame_id = who_;
    const std::int64_t now = monotonicNs();
    h.stamp.sec = static_cast<std::int32_t>(now / 1'000'000'000);
    h.stamp.nanosec = static_cast<std::uint32_t>(now % 1'000'000'000);
    out.push(h);
    return keel::ReturnCode::Ok;
  }

 private:
  std::string who_;
};

class BenchDdsEcho : public keel::Component {
 public:
  keel::InputDataPort<Header> in{this, "in"};
  keel::OutputDataPort<Header> out{this, "out"};
  keel::ReturnCode onExecute() override {
    while (auto h = in.pop()) out.push(*h);
    return keel::ReturnCode::Ok;
  }
};

class BenchDdsSink : public keel::Component {
 public:
  keel::InputDataPort<Header> in{this, "in"};
  keel::ReturnCode onInitialize() override {
    page_ = mapPage(property<std::string>("page", ""));
    return page_ != nullptr ? keel::ReturnCode::Ok : keel::ReturnCode::PreconditionNotMet;
  }
  keel::ReturnCode onExecute() override {
    const std::int64_t now = monotonicNs();
    while (auto h = in.pop()) {
      const std::int64_t sent = std::int64_t{h->stamp.sec} * 1'000'000'000 + h->stamp.nanosec;
      const auto k = page_->received.fetch_add(1, std::memory_order_relaxed);
      if (k < BenchPage::kMaxSamples) page_->latency_ns[k].store(now - sent, std::memory_order_relaxed);
      int who = 0;
      std::from_chars(h->frame_id.data(), h->frame_id.data() + h->frame_id.size(), who);
      if (who != last_) {
        last_ = who;
        page_->first_ns.store(now, std::memory_order_relaxed);
        page_->active_pid.store(who, std::memory_order_release);
      }
    }
    return keel::ReturnCode::Ok;
  }

 private:
  BenchPage* page_ = nullptr;
  int last_ = 0;
};

}  // namespace
}  // namespace keel_bench

KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchDdsStamp, "BenchDdsStamp")
KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchDdsEcho, "BenchDdsEcho")
KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchDdsSink, "BenchDdsSink")
