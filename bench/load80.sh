# Sourced by the bench/run_*.sh scripts: start_load80 runs stress-ng at 80% on both CPUs for
# the rest of the script (stopped on exit) and lets it settle. Needs stress-ng (scripts/deps.sh).
start_load80() {
  echo "## under load: stress-ng --cpu 2 --cpu-load 80"
  stress-ng --cpu 2 --cpu-load 80 --timeout 3600 >/dev/null 2>&1 &
  local stress=$!
  trap "kill $stress 2>/dev/null || true" EXIT
  sleep 2
}
