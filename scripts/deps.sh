#!/usr/bin/env bash
# Installs what keel needs to build, test and benchmark on Debian 12 (bookworm), and the
# packages named as arguments (`scripts/deps.sh clang-14`: what another script needs).
# Quiet and offline when everything is already installed, so scripts/test.sh can call it
# every time; otherwise one line, with apt's output in a log shown only if it fails. Runs
# apt-get as root, through sudo when not root.
set -euo pipefail

packages=(
  cmake ninja-build g++
  ccache  # the presets compile through it (docs/decisions/0020-ci-time.md)
  libgtest-dev libgmock-dev libpugixml-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libbenchmark-dev
  libboost-dev  # Beast and Asio (header-only): the monitor's HTTP/WebSocket server; Math: chi-square
  libeigen3-dev  # the state estimator's linear algebra (components/estimators, decision 0024)
  python3 python3-matplotlib
  stress-ng
  erlang-base
  cyclonedds-tools  # ddsperf (keel bench isolation) and idlc (message types)
  cyclonedds-dev  # CycloneDDS C API: DDS ports visible to ROS 2 (src/dds, decision 0018)
  iproute2  # ip netns: the redundancy test's two hosts (tests/dds/redundancy_test.py)
  graphviz  # dot, for the docs' `keel graph` examples (tests/docs/examples_test.py)
)
packages+=("$@")  # a script's own (scripts/fuzz.sh: clang and libFuzzer)

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  echo "deps.sh: not a Debian system (no dpkg/apt-get); install these yourself:" >&2
  echo "  ${packages[*]}" >&2
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  if [[ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done
((${#missing[@]} == 0)) && exit 0

if [[ $(id -u) -eq 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "deps.sh: need root to install: ${missing[*]} (run as root, or install sudo)" >&2
  exit 1
fi

# One line on the screen; apt's own output goes to a log, shown only if it fails.
log="${TMPDIR:-/tmp}/keel-deps.log"
echo "deps.sh: installing ${#missing[@]} Debian packages (${missing[*]}); apt's output: $log"
if ! { "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update &&
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"; } >"$log" 2>&1; then
  echo "deps.sh: apt-get failed; the end of $log:" >&2
  tail -n 20 "$log" >&2
  exit 1
fi
