#!/usr/bin/env bash
# Installs the independent implementations keel's tests talk to (docs/testing.md, "Real
# peers"): PyPI's `mcap` reader, ROS 2's rclpy with its message packages and colcon (the
# workspace build tool) in a venv (tests/peers/venv), Foxglove's WebSocket client and
# puppeteer-core from npm (tests/peers/node_modules, from the lockfile), and Debian's headless
# Chromium for the monitor's page. Quiet and offline when all is installed already, so
# scripts/test.sh calls it every time; otherwise one line, with the installers' output in a log
# shown only if one fails.
#   scripts/peers.sh           all of them (scripts/test.sh)
#   scripts/peers.sh python    the venv alone: rclpy for scripts/demo.sh's ros2 experiment
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

only=${1:-}
case "$only" in
  "" | python) ;;
  *) echo "usage: scripts/peers.sh [python]" >&2 && exit 2 ;;
esac
if [[ "$only" == python ]]; then
  scripts/deps.sh python3-venv
else
  scripts/deps.sh python3-venv chromium fonts-dejavu-core
fi

peers=tests/peers
log="${TMPDIR:-/tmp}/keel-peers.log"
stamp_py="$peers/venv/.installed"
stamp_js="$peers/node_modules/.installed"
want_py=$(sha256sum "$peers/requirements.txt" | cut -c1-64)
want_js=$(sha256sum "$peers/package-lock.json" | cut -c1-64)
have_py=$(cat "$stamp_py" 2>/dev/null || true)
have_js=$(cat "$stamp_js" 2>/dev/null || true)
[[ "$only" == python ]] && have_js=$want_js  # not asked for
[[ "$have_py" == "$want_py" && "$have_js" == "$want_js" ]] && exit 0

if [[ "$only" == python ]]; then
  echo "peers.sh: installing rclpy, mcap and colcon from PyPI in $peers/venv; output: $log"
else
  echo "peers.sh: installing the test peers (PyPI: mcap, rclpy, colcon; npm: @foxglove/ws-protocol, ws, puppeteer-core); output: $log"
fi
: >"$log"
fail() {
  echo "peers.sh: $1 failed; the end of $log:" >&2
  tail -n 20 "$log" >&2
  exit 1
}
if [[ "$have_py" != "$want_py" ]]; then
  # Debian's interpreter, not one on PATH (pyenv's may lack venv); its own packages stay visible.
  { rm -rf "$peers/venv" && /usr/bin/python3 -m venv "$peers/venv" &&
    "$peers/venv/bin/pip" install --disable-pip-version-check -q -r "$peers/requirements.txt"; } >>"$log" 2>&1 ||
    fail "pip install"
  echo "$want_py" >"$stamp_py"
fi
if [[ "$have_js" != "$want_js" ]]; then
  # puppeteer-core downloads no browser: the tests drive /usr/bin/chromium.
  (cd "$peers" && npm ci --no-audit --no-fund) >>"$log" 2>&1 || fail "npm ci"
  echo "$want_js" >"$stamp_js"
fi
