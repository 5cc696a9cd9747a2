#!/usr/bin/env bash
# Installs the independent implementations keel's tests talk to (docs/testing.md, "Real
# peers"): PyPI's `mcap` reader and ROS 2's rclpy with its message packages in a venv
# (tests/peers/venv), Foxglove's WebSocket client and
# puppeteer-core from npm (tests/peers/node_modules, from the lockfile), and Debian's headless
# Chromium for the monitor's page. Quiet and offline when all is installed already, so
# scripts/test.sh calls it every time; otherwise one line, with the installers' output in a log
# shown only if one fails.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

scripts/deps.sh python3-venv chromium fonts-dejavu-core

peers=tests/peers
log="${TMPDIR:-/tmp}/keel-peers.log"
stamp_py="$peers/venv/.installed"
stamp_js="$peers/node_modules/.installed"
want_py=$(sha256sum "$peers/requirements.txt" | cut -c1-64)
want_js=$(sha256sum "$peers/package-lock.json" | cut -c1-64)
have_py=$(cat "$stamp_py" 2>/dev/null || true)
have_js=$(cat "$stamp_js" 2>/dev/null || true)
[[ "$have_py" == "$want_py" && "$have_js" == "$want_js" ]] && exit 0

echo "peers.sh: installing the test peers (PyPI: mcap, rclpy; npm: @foxglove/ws-protocol, ws, puppeteer-core); output: $log"
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
