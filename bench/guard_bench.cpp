// What the guard costs per callback when nothing faults (issue: fault detection, ≤ 50 ns):
// a plain virtual call of onExecute, the same call under runtime::guarded, and the whole of
// runtime::invoke as executors use it (guard, injection check, bookkeeping).
//   build/bin/keel_bench_guard --benchmark_repetitions=20 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "keel/component.hpp"
#include "runtime/guard.hpp"
#include "runtime/invoke.hpp"

namespace {

class Cheap : public keel::Component {
 public:
  keel::ReturnCode onExecute() override {
    benchmark::DoNotOptimize(++n_);
    return keel::ReturnCode::Ok;
  }

 private:
  long n_ = 0;
};

keel::Component* make() {
  static Cheap c;
  return &c;
}

void BM_DirectVirtualCall(benchmark::State& state) {
  keel::Component* c = make();
  for (auto _ : state) benchmark::DoNotOptimize(c->onExecute());
}
BENCHMARK(BM_DirectVirtualCall);

void BM_GuardedCall(benchmark::State& state) {
  keel::runtime::installSignalHandlers();
  keel::Component* c = make();
  for (auto _ : state) {
    auto out = keel::runtime::guarded([c] { return c->onExecute(); });
    benchmark::DoNotOptimize(out.kind);
  }
}
BENCHMARK(BM_GuardedCall);

void BM_Invoke(benchmark::State& state) {
  keel::runtime::installSignalHandlers();
  keel::Component* c = make();
  for (auto _ : state) benchmark::DoNotOptimize(keel::runtime::invoke(*c, keel::runtime::Callback::Execute));
}
BENCHMARK(BM_Invoke);

}  // namespace

BENCHMARK_MAIN();
