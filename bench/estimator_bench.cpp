// What the stock state estimator (components/estimators) costs per sample: one step of the bank
// as the robot runs it (robot/estimation.xml: 2 states, 2 inputs, 3 measurements, so a full
// filter and 3 leave-one-out filters), fault-free, and with the left encoder dead and excluded
// (a full filter and 2). The robot's motion task runs it once per 20 ms status frame.
//   build/bin/keel_bench_estimator --benchmark_repetitions=20 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>

#include "components/estimators/estimator_bank.hpp"

namespace {

using keel::components::EstimatorBank;
using keel::components::LinearModel;
using keel::components::Matrix;
using keel::components::Vector;

// The robot's model (robot/estimation.xml).
LinearModel robot() {
  LinearModel m;
  m.A = Matrix(2, 2);
  m.A << 0.875173, 0, 0, 0.875173;
  m.B = Matrix(2, 2);
  m.B << 0.124827, 0, 0, 0.124827;
  m.C = Matrix(3, 2);
  m.C << 1.069731, 0, 0, 1.069731, -0.024310, 0.024310;
  m.D = Matrix(3, 2);
  m.D << -0.069731, 0, 0, -0.069731, 0, 0;
  m.Q = Matrix(Vector::Constant(2, 0.5).asDiagonal());
  m.R = Matrix(3, 3);
  m.R.setZero();
  m.R.diagonal() << 11.6, 11.6, 0.000026;
  m.x0 = Vector::Zero(2);
  m.P0 = Matrix(m.Q + Matrix::Identity(2, 2));
  return m;
}

// Samples of a robot driving ahead at 60 rpm, with the model's noise: a ring the loop walks.
struct Samples {
  explicit Samples(bool dead_left) {
    std::mt19937_64 rng(1);  // NOLINT(cert-msc51-cpp): the same samples every run, on purpose
    std::normal_distribution<double> e(0, 3.4), g(0, 0.005);
    for (auto& s : y) {
      s = Vector(3);
      s << (dead_left ? 0.0 : 60 + e(rng)), 60 + e(rng), g(rng);
    }
  }
  std::array<Vector, 256> y;
};

void BM_BankStep(benchmark::State& state) {
  const bool excluded = state.range(0) != 0;
  EstimatorBank bank;
  bank.configure(robot(), 5, 1e-6, 0);
  const Samples healthy(false);
  const Samples samples(excluded);
  Vector u(2);
  u << 60, 60;
  std::size_t i = 0;
  for (int k = 0; k < 200; ++k) bank.step(u, healthy.y[i++ % healthy.y.size()], 0b111);  // settled
  for (int k = 0; k < 100; ++k) bank.step(u, samples.y[i++ % samples.y.size()], 0b111);  // excluded, if dead
  if (excluded != !bank.trusted(0)) state.SkipWithError("the dead encoder was not excluded as set up");
  for (auto _ : state) {
    auto v = bank.step(u, samples.y[i++ % samples.y.size()], 0b111);
    benchmark::DoNotOptimize(v);
  }
}
BENCHMARK(BM_BankStep)->Arg(0)->Arg(1)->ArgNames({"sensor_excluded"});

}  // namespace

BENCHMARK_MAIN();
