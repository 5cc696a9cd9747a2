#!/usr/bin/env bash
# The README's first command: builds keel and runs its main job. Today that is the fault
# detection example (examples/02_fault_detection): three components, two of them with bugs
# that strike while running (a segmentation fault, an exception), and faults keel injects
# itself (an out-of-range reading, a hang). keel detects each one — around the callback, on
# the port, by the watchdog — handles it by the profile's rules (a hung callback interrupted
# and reset, a crashed sensor contained), logs it, and keeps the rest running. The simulated robot of the
# paper replaces this as the main job when it lands.
#   scripts/demo.sh [seconds]     (default 3; the fault log goes to demo.jsonl)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
scripts/deps.sh
cmake -S . -B build -G Ninja >/dev/null
cmake --build build --target keel_cli fault_demo_components
build/bin/keel run examples/02_fault_detection/app.xml --duration "${1:-3}" --log demo.jsonl \
  --inject examples/02_fault_detection/scenario.xml
echo
echo "fault log: demo.jsonl (one JSON record per line); detections, actions and recoveries:"
grep -E '"event":"(detected|action|recovered)"' demo.jsonl || true
