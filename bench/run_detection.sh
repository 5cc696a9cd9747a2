#!/usr/bin/env bash
# Detection latency per detector, idle and under 80% CPU load (stress-ng), as docs/performance.md
# reports it. Needs a build (build/bin/keel_bench_detection) and stress-ng (scripts/deps.sh).
#   bench/run_detection.sh [N]        (N injections per kind and policy, default 1000)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source bench/load80.sh
n=${1:-1000}
bin=build/bin/keel_bench_detection
echo "## idle"
"$bin" --n "$n" --json build/detection_idle.jsonl
echo
start_load80
"$bin" --n "$n" --json build/detection_load80.jsonl
