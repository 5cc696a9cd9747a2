#!/usr/bin/env bash
# Detection latency per detector, idle and under 80% CPU load (stress-ng), as docs/performance.md
# reports it. Needs a build (build/bin/keel_bench_detection) and stress-ng (scripts/deps.sh).
#   bench/run_detection.sh [N]        (N injections per kind and policy, default 1000)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
n=${1:-1000}
bin=build/bin/keel_bench_detection
echo "## idle"
"$bin" --n "$n" --json build/detection_idle.jsonl
echo
echo "## under load: stress-ng --cpu 2 --cpu-load 80"
stress-ng --cpu 2 --cpu-load 80 --timeout 3600 >/dev/null 2>&1 &
stress=$!
trap 'kill $stress 2>/dev/null || true' EXIT
sleep 2
"$bin" --n "$n" --json build/detection_load80.jsonl
