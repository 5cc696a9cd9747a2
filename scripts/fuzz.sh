#!/usr/bin/env bash
# Builds and runs keel's libFuzzer targets (fuzz/, docs/fuzzing.md).
#
#   scripts/fuzz.sh --list             the targets, a line each
#   scripts/fuzz.sh TARGET SECONDS     runs one for SECONDS
#   scripts/fuzz.sh --all SECONDS      runs each for SECONDS, as many at once as there are
#                                      cores ($KEEL_FUZZ_PARALLEL to choose; what CI does)
#
# The targets are built by the `asan-ubsan` preset (clang 14, ASan+UBSan, in build-asan/); the
# packages they need (clang-14, libclang-rt-14-dev, libfuzzer-14-dev) are installed by
# scripts/deps.sh. Each run starts from the checked-in seeds (fuzz/corpus/TARGET, read only)
# and keeps what it finds in build-asan/corpus/TARGET; XML targets use fuzz/xml.dict,
# monitor_client fuzz/monitor_client.dict. A crash, a leak, a UBSan finding, a timeout (10 s
# per input) or a failed check exits non-zero, with the input kept in
# build-asan/findings/TARGET/ and the command that reproduces it printed.
# Jobs for the build: $KEEL_JOBS, else the number of cores.
set -euo pipefail

usage() { sed -n '2,15s/^# \{0,1\}//p' "$0"; }

cd "$(dirname "${BASH_SOURCE[0]}")/.."
targets=(profile_component profile_composite profile_package profile_system profile_types profile_node scenario
  motion_board monitor_client mcap_reader opros_archive dds_sample)

case "${1:-}" in
  --list) printf '%s\n' "${targets[@]}"; exit 0 ;;
  -h | --help) usage; exit 0 ;;
  --all) (($# == 2)) || { usage >&2; exit 2; } ;;
  "") usage >&2; exit 2 ;;
  *)
    (($# == 2)) || { usage >&2; exit 2; }
    [[ " ${targets[*]} " == *" $1 "* ]] || { echo "fuzz.sh: no target '$1' (scripts/fuzz.sh --list)" >&2; exit 2; }
    ;;
esac
seconds=$2
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2; }

scripts/deps.sh clang-14 libclang-rt-14-dev libfuzzer-14-dev
jobs=${KEEL_JOBS:-$(nproc)}
scripts/lib/configure.sh asan-ubsan >/dev/null
cmake --build build-asan --target keel_fuzz --parallel "$jobs"

# libFuzzer's own leak check is ASan's; UBSan stops at its first finding.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

run() {
  local target=$1 work=build-asan/corpus/$1 findings=build-asan/findings/$1
  mkdir -p "$work" "$findings"
  local dict=()
  case $target in
    motion_board | mcap_reader | opros_archive | dds_sample) ;;
    monitor_client) dict=(-dict=fuzz/monitor_client.dict) ;;
    *) dict=(-dict=fuzz/xml.dict) ;;
  esac
  echo "fuzz.sh: $target for $seconds s (seeds: fuzz/corpus/$target, corpus: $work)"
  # The first corpus directory gets what is new; the seeds stay as checked in.
  if ! build-asan/fuzz/"$target" "$work" "fuzz/corpus/$target" "${dict[@]}" -max_total_time="$seconds" \
    -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$findings/" -print_final_stats=1 2>"$findings/log"; then
    tail -n 40 "$findings/log" >&2
    echo "fuzz.sh: $target FAILED; the input is in $findings/; reproduce: build-asan/fuzz/$target $findings/<file>" >&2
    return 1
  fi
  grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+.*DONE' "$findings/log" | sed "s/^/  /" || true
}

if [[ $1 == --all ]]; then
  # Each target is one single-threaded process: one per core, each printing when it is done.
  parallel=${KEEL_FUZZ_PARALLEL:-$(nproc)}
  failed=()
  declare -A running=()
  reap() {
    local pid status=0
    wait -n -p pid || status=$?
    local t=${running[$pid]}
    unset "running[$pid]"
    ((status == 0)) || failed+=("$t")
    cat "build-asan/findings/$t/summary"
  }
  for t in "${targets[@]}"; do
    while ((${#running[@]} >= parallel)); do reap; done
    mkdir -p "build-asan/findings/$t"
    run "$t" >"build-asan/findings/$t/summary" 2>&1 &
    running[$!]=$t
  done
  while ((${#running[@]} > 0)); do reap; done
  if ((${#failed[@]} > 0)); then
    echo "fuzz.sh: failed: ${failed[*]}" >&2
    exit 1
  fi
else
  run "$1"
fi
