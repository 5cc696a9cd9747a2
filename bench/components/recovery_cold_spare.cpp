// The cold alternative of the recovery-latency benchmark, alone in its library
// (libkeel_bench_cold_spare.so): no component of the benchmark's packages is in it, so the
// library is not mapped until the fault manager loads it for a replacement.
#include <keel/component.hpp>

#include <cstdint>

namespace keel_bench {

class BenchColdSpare : public keel::Component {
 public:
  keel::ReturnCode onExecute() override {
    ++steps_;
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t steps_ = 0;
};

}  // namespace keel_bench

KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchColdSpare, "BenchColdSpare")
