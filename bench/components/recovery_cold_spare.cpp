// The cold alternative of the recovery-latency benchmark, alone in its library
// (libkeel_bench_cold_spare.so): no component of the benchmark's packages is in it, so the
// library is not mapped until the fault manager loads it for a replacement.
#include "stepper.hpp"

KEEL_REGISTER_COMPONENT_AS(keel_bench::Stepper, "BenchColdSpare")
