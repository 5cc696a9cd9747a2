#!/usr/bin/env bash
# The README's first command: builds keel and runs its main job, the paper's test robot
# (docs/robot.md). The simulated robot follows a red target across a room with obstacles, first
# without faults, then through the paper's experiments, each injected while it drives: a
# segmentation fault, the vision's process killed with `kill -9` (twice), an unplugged sonar, a
# lying sonar, the left wheel's driver losing power (Fig. 6), an obstacle avoider that keeps
# crashing. Then diagnosis by state estimation (robot/estimation.xml), which the paper could not
# do: the left encoder going dead, which the paper's detector takes for the motor and stops the
# robot for, accused as the sensor it is while the robot drives on (`estimation_encoder_left_dead`),
# and Fig. 6's motor off accused as the actuator's (`estimation_fig6_left_motor_off`), each with
# a plot of the estimator's test against its threshold. Last, `ros2`: a ROS 2 node (rclpy, from PyPI), started and supervised by keel, drives
# the robot over DDS from the sonar ranges keel publishes, is killed with `kill -9` and restarted
# by keel, then sends one corrupted command (a `range` fault of the node) and is restarted again
# (robot/ros2/); then `ros2_standby`: the same node as a lifecycle node with a hot standby, which
# takes over from the killed node, and from the one that sent garbage, with the wheels never
# stopped. For each
# run keel prints what it detected, how it handled it and the mission's outcome, and for a killed
# process how soon its standby took over; the fault logs, MCAP recordings and plots (trajectory
# with the faults marked, Fig. 6's rpm and detection) go to demo/. While each runs, its live
# monitor is at the address printed (KEEL_DEMO_MONITOR sets it, default 127.0.0.1:8765).
#   scripts/demo.sh [experiment...]   (default: nominal segfault vision_killed sonar_unplugged
#                                      sonar_wrong fig6_left_motor_off avoidance_replaced
#                                      estimation_encoder_left_dead estimation_fig6_left_motor_off
#                                      ros2 ros2_standby; see robot/scenarios; estimation_X runs
#                                      scenario X with robot/estimation.xml; robot/ros2.xml for
#                                      the last two)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Each death of a component process in fault log $1, from its `detected` and `host` records
# (docs/fault-log.md): who took over (a standby, or a process started anew) and when.
takeovers() {
  python3 - "$1" <<'PY'
import json, sys
records = sorted((json.loads(line) for line in open(sys.argv[1]) if line.strip()), key=lambda r: r["t_ns"])
killed = {r["fault_id"]: r["t_ns"] for r in records if r["event"] == "injected"}  # by --inject
seen, fresh = None, False  # the `detected` record of the last death; a standby since?
for r in records:
    after = (r["t_ns"] - seen["t_ns"]) / 1e3 if seen else 0.0  # us since the death was seen
    if r["event"] == "detected" and r.get("kind") == "process":
        seen, fresh = r, False
        kill = killed.get(r["fault_id"])
        print(f"  {r['t_ns'] / 1e9:6.3f} s  {r['detail']}"
              + (f", seen {(r['t_ns'] - kill) / 1e3:.0f} us after the kill" if kill else ""))
    elif not seen:
        continue
    elif r["event"] == "host" and r["phase"] in ("took_over", "respawned"):
        who = "its standby" if r["phase"] == "took_over" else "a new process (no standby was ready)"
        print(f"           {who}, pid {r['pid']}, took over {after:.0f} us after the death was seen")
    elif r["event"] == "recovered" and r["fault_id"] == seen["fault_id"]:
        print(f"           {seen['component']} ran again {after / 1e3:.1f} ms after it, on its next input")
    elif r["event"] == "host" and r["phase"] == "standby" and not fresh:
        fresh = True
        print(f"           a fresh standby, pid {r['pid']}, was ready {after / 1e3:.0f} ms after it")
PY
}

scripts/deps.sh
# The build's output in a log, shown only if it fails: the first screen is the robot's.
mkdir -p demo
echo "demo.sh: building keel and the robot (a few minutes the first time); output: demo/build.log"
if ! { cmake -S . -B build -G Ninja &&
  cmake --build build --target keel_cli keel_robot keel_stock keel_motion_board; } >demo/build.log 2>&1; then
  echo "demo.sh: the build failed; the end of demo/build.log:" >&2
  tail -n 30 demo/build.log >&2
  exit 1
fi
monitor=${KEEL_DEMO_MONITOR:-127.0.0.1:8765}  # the live monitor's address (docs/monitor.md)
experiments=("$@")
((${#experiments[@]})) || experiments=(nominal segfault vision_killed sonar_unplugged sonar_wrong fig6_left_motor_off
                                       avoidance_replaced estimation_encoder_left_dead
                                       estimation_fig6_left_motor_off ros2 ros2_standby)
for e in "${experiments[@]}"; do
  if [[ "$e" == ros2 || "$e" == ros2_standby ]]; then
    # A ROS 2 node drives the robot (robot/ros2.xml, robot/ros2/): rclpy from PyPI, in the test
    # peers' venv; without it (no network, no python3-venv) this experiment alone is skipped.
    # ros2_standby: the same node as a lifecycle node with a standby (ros2/wander_lifecycle.xml).
    standby=()
    echo
    if [[ "$e" == ros2 ]]; then
      echo "=== ros2: a ROS 2 node keel supervises drives the robot; killed with kill -9, then sending garbage, it is restarted ==="
    else
      standby=(--standby)
      echo "=== ros2_standby: the node as a lifecycle node with a hot standby; killed with kill -9, then sending garbage, its standby takes over each time ==="
    fi
    if ! scripts/peers.sh python; then
      echo "demo.sh: skipping $e: rclpy could not be installed (scripts/peers.sh python, above)" >&2
      continue
    fi
    python3 robot/ros2/experiment.py "${standby[@]}" --keel build/bin/keel --python tests/peers/venv/bin/python \
      --out "demo/$e" --monitor "$monitor" || echo "demo.sh: the $e experiment did not complete (above)" >&2
    python3 robot/plot_run.py --trace "demo/$e.csv" --log "demo/$e.jsonl" --out "demo/$e" || true
    continue
  fi
  inject=()
  profile=robot/navigation.xml
  scenario=$e
  if [[ "$e" == estimation_* ]]; then  # the same scenario, diagnosed by state estimation
    profile=robot/estimation.xml
    scenario=${e#estimation_}
  fi
  [[ "$scenario" == nominal ]] || inject=(--inject "robot/scenarios/$scenario.xml")
  echo
  echo "=== $e ==="
  # Live on the monitor's page while it drives (the same port for every experiment: an open
  # page follows from one to the next), and recorded for Foxglove in demo/$e.mcap.
  build/bin/keel run "$profile" --duration 60 --log "demo/$e.jsonl" "${inject[@]}" \
    --set "referee.trace=demo/$e.csv" --monitor "$monitor" --record "demo/$e.mcap" >"demo/$e.out" &
  run=$!
  for _ in $(seq 100); do grep -q '^monitor: ' "demo/$e.out" 2>/dev/null && break; sleep 0.1; done
  grep '^monitor: ' "demo/$e.out" || true
  wait "$run"
  grep -v '^monitor: ' "demo/$e.out" | tail -n 12
  echo "--- detections, actions, recoveries (demo/$e.jsonl):"
  grep -E '"event":"(injected|detected|action|recovered)"' "demo/$e.jsonl" | cut -c1-200 || echo "(none)"
  if grep -qE '"phase":"(took_over|respawned)"' "demo/$e.jsonl"; then
    echo "--- component processes killed, and who took over:"
    takeovers "demo/$e.jsonl"
  fi
  python3 robot/plot_run.py --trace "demo/$e.csv" --log "demo/$e.jsonl" --out "demo/$e" || true
  if [[ "$profile" == robot/estimation.xml ]]; then  # its test and threshold, from the recording
    build/bin/keel report "demo/$e.mcap" --plots "demo/$e/recorded" | grep estimation.svg || true
  fi
done
