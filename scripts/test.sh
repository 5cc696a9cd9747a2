#!/usr/bin/env bash
# The README's test command: installs dependencies (scripts/deps.sh), configures, builds and
# runs the tests of one build mode, exiting non-zero on any failure.
#
#   scripts/test.sh          build/       the full suite (the README's plain build)
#   scripts/test.sh asan     build-asan/  the full suite under ASan + UBSan (UBSan fatal; clang 14,
#                                         the build that also holds the fuzz targets)
#   scripts/test.sh tsan     build-tsan/  the tests labelled `concurrency` or `scenario` under TSan
#
# Each mode is the CMake preset of the same name in CMakePresets.json (asan = asan-ubsan), so
# `cmake --workflow --preset <name>` does the same by hand. Arguments after the mode go to
# ctest (e.g. `scripts/test.sh asan -R Guard`). Build jobs: $KEEL_JOBS, else 2 under CI,
# else the number of cores; tests run two at a time.
set -euo pipefail

usage() { sed -n '2,14s/^# \{0,1\}//p' "$0"; }

mode=${1:-default}
extra=()  # the packages a mode needs beyond scripts/deps.sh's own
(($# > 0)) && shift
case "$mode" in
  default) preset=default ;;
  asan | asan-ubsan) preset=asan-ubsan; extra=(clang-14 libclang-rt-14-dev libfuzzer-14-dev) ;;
  tsan) preset=tsan ;;
  -h | --help) usage; exit 0 ;;
  *) echo "test.sh: unknown mode '$mode'" >&2; usage >&2; exit 2 ;;
esac

cd "$(dirname "${BASH_SOURCE[0]}")/.."

scripts/deps.sh "${extra[@]}"
scripts/peers.sh  # the independent implementations the interop tests talk to

# Sanitizer runtime options, also set by the test presets (here for anything ctest starts).
case "$preset" in
  asan-ubsan)
    # libkeel's guard turns SIGSEGV & co. inside a callback into faults: ASan must leave those
    # signals to it.
    export ASAN_OPTIONS="allow_user_segv_handler=1:handle_segv=0:handle_sigbus=0:handle_sigfpe=0:handle_sigill=0:handle_abort=0:detect_leaks=1"
    export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
    ;;
  tsan)
    # CycloneDDS is not built with TSan: tests/tsan.supp says which of its reports are not keel's.
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan.supp"
    ;;
esac

if [[ -n "${KEEL_JOBS:-}" ]]; then
  jobs=$KEEL_JOBS
elif [[ -n "${CI:-}" ]]; then
  jobs=2
else
  jobs=$(nproc 2>/dev/null || echo 2)
fi

# The sanitizers of GCC 12 and clang 14 cannot map their shadow memory when the kernel randomises
# mmap with more than 28 bits; running the tests without ASLR avoids it.
run_tests=(ctest --preset "$preset")
if [[ "$preset" != default ]]; then
  rnd_bits=$(cat /proc/sys/vm/mmap_rnd_bits 2>/dev/null || echo 28)
  if ((rnd_bits > 28)); then
    if setarch "$(uname -m)" -R true 2>/dev/null; then
      run_tests=(setarch "$(uname -m)" -R "${run_tests[@]}")
    else
      echo "test.sh: warning: vm.mmap_rnd_bits=$rnd_bits and ASLR cannot be disabled;" \
           "sanitized binaries may fail to start (sysctl vm.mmap_rnd_bits=28 fixes it)" >&2
    fi
  fi
fi

start=$SECONDS
echo "== test.sh $mode: configure (preset $preset)"
scripts/lib/configure.sh "$preset"
echo "== test.sh $mode: build (-j$jobs)"
cmake --build --preset "$preset" --parallel "$jobs"
echo "== test.sh $mode: test"
"${run_tests[@]}" "$@"
echo "== test.sh $mode: passed in $((SECONDS - start)) s"
