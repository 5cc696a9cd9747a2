#!/usr/bin/env bash
# The README's first command: builds keel and runs its main job, the paper's test robot
# (docs/robot.md). The simulated robot follows a red target across a room with obstacles, first
# without faults, then through the paper's experiments, each injected while it drives: a
# segmentation fault, an unplugged sonar, a lying sonar, the left wheel's driver losing power
# (Fig. 6), an obstacle avoider that keeps crashing. For each run keel prints what it detected,
# how it handled it and the mission's outcome; the fault logs and plots (trajectory with the
# faults marked, Fig. 6's rpm and detection) go to demo/.
#   scripts/demo.sh [experiment...]   (default: nominal segfault sonar_unplugged sonar_wrong
#                                      fig6_left_motor_off avoidance_replaced; see robot/scenarios)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
scripts/deps.sh
cmake -S . -B build -G Ninja >/dev/null
cmake --build build --target keel_cli keel_robot keel_stock keel_motion_board
mkdir -p demo
experiments=("$@")
((${#experiments[@]})) || experiments=(nominal segfault sonar_unplugged sonar_wrong fig6_left_motor_off avoidance_replaced)
for e in "${experiments[@]}"; do
  inject=()
  [[ "$e" == nominal ]] || inject=(--inject "robot/scenarios/$e.xml")
  echo
  echo "=== $e ==="
  build/bin/keel run robot/navigation.xml --duration 60 --log "demo/$e.jsonl" "${inject[@]}" \
    --set "referee.trace=demo/$e.csv" | tail -n 12
  echo "--- detections, actions, recoveries (demo/$e.jsonl):"
  grep -E '"event":"(injected|detected|action|recovered)"' "demo/$e.jsonl" | cut -c1-200 || echo "(none)"
  python3 robot/plot_run.py --trace "demo/$e.csv" --log "demo/$e.jsonl" --out "demo/$e" || true
done
