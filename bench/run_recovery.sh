#!/usr/bin/env bash
# Recovery latency per handling mechanism, idle and under 80% CPU load (stress-ng), as
# docs/performance.md reports it. Builds keel_bench_recovery in BUILD_DIR (default build/, the
# README's RelWithDebInfo build) and needs stress-ng (scripts/deps.sh).
#   bench/run_recovery.sh [N] [BUILD_DIR]     (N faults per mechanism and policy, default 1000)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source bench/load80.sh
n=${1:-1000}
build=${2:-build}
[ -f "$build/CMakeCache.txt" ] || cmake -S . -B "$build" -G Ninja >/dev/null
cmake --build "$build" --target keel_bench_recovery >/dev/null
bin=$build/bin/keel_bench_recovery
echo "## idle"
"$bin" --n "$n" --load 0 --json "$build/recovery_idle.jsonl"
echo
echo "## idle, /dev/cpu_dma_latency held at 0 (idle CPUs poll instead of halting)"
"$bin" --n "$n" --load 0 --low-latency --json "$build/recovery_idle_lowlat.jsonl"
echo
start_load80
"$bin" --n "$n" --load 80 --json "$build/recovery_load80.jsonl"
