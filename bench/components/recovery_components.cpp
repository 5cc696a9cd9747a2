// Components of the recovery-latency benchmark (bench/recovery_bench.cpp): a victim whose
// onExecute is trivial (the `recovered` moment includes one of its steps), and the alternative
// preloaded in its place. The cold alternative lives in its own library
// (recovery_cold_spare.cpp), which nothing else in the benchmark's packages uses, so that a
// cold replacement really dlopens it at fault time.
#include <keel/component.hpp>

#include <cstdint>

namespace keel_bench {

class BenchVictim : public keel::Component {
 public:
  keel::ReturnCode onExecute() override {
    ++steps_;
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t steps_ = 0;
};

class BenchSpare : public keel::Component {
 public:
  keel::ReturnCode onExecute() override {
    ++steps_;
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t steps_ = 0;
};

}  // namespace keel_bench

KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchVictim, "BenchVictim")
KEEL_REGISTER_COMPONENT_AS(keel_bench::BenchSpare, "BenchSpare")
