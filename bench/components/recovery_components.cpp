// Components of the recovery-latency benchmark (bench/harness/recovery.cpp, `keel bench recovery`): a victim whose
// onExecute is trivial (the `recovered` moment includes one of its steps), and the alternative
// preloaded in its place. The cold alternative lives in its own library
// (recovery_cold_spare.cpp), which nothing else in the benchmark's packages uses, so that a
// cold replacement really dlopens it at fault time.
#include "stepper.hpp"

KEEL_REGISTER_COMPONENT_AS(keel_bench::Stepper, "BenchVictim")
KEEL_REGISTER_COMPONENT_AS(keel_bench::Stepper, "BenchSpare")
