// What the guard costs per callback when nothing faults (issue: fault detection, ≤ 50 ns):
// a plain virtual call of onExecute, the same call under runtime::guarded, and the whole of
// runtime::invoke as executors use it (guard, injection check, bookkeeping); and the same invoke
// of a component written against the OPRoS API, through the keel adapter that runs it (src/opros).
//   build/bin/keel_bench_guard --benchmark_repetitions=20 --benchmark_report_aggregates_only=true
#include <Component.h>
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

class CheapOpros : public ::Component {
 public:
  ReturnType onExecute() override {
    benchmark::DoNotOptimize(++n_);
    return OPROS_SUCCESS;
  }

 private:
  long n_ = 0;
};

}  // namespace

// libkeel_opros's entry point, as keel's loader finds it in an OPRoS library.
extern "C" keel::Component* keel_opros_adapter(void* get_component, void* release_component);

namespace {

::Component* makeCheapOpros() { return new CheapOpros(); }
void releaseCheapOpros(::Component* c) { delete c; }

void BM_InvokeOpros(benchmark::State& state) {
  keel::runtime::installSignalHandlers();
  std::unique_ptr<keel::Component> adapter(
      keel_opros_adapter(reinterpret_cast<void*>(&makeCheapOpros), reinterpret_cast<void*>(&releaseCheapOpros)));
  for (auto _ : state) benchmark::DoNotOptimize(keel::runtime::invoke(*adapter, keel::runtime::Callback::Execute));
}
BENCHMARK(BM_InvokeOpros);

}  // namespace

BENCHMARK_MAIN();
