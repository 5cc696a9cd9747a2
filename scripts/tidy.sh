#!/usr/bin/env bash
# Runs clang-tidy with the checks in .clang-tidy over keel's own sources (and, through them,
# keel's headers), using the compile database of a build tree
# (docs/decisions/0008-format-and-lint.md).
#
#   scripts/tidy.sh [--no-analyzer] [BUILD_DIR]    default: build
#
# --no-analyzer leaves out the static analyzer (clang-analyzer-*), more than half of the run's
# time: what CI runs within its budget. Before a commit, run it whole.
#
# BUILD_DIR/compile_commands.json is written by CMake's configure step (CMAKE_EXPORT_COMPILE_COMMANDS
# is on); when it is missing the tree is configured (not built): `cmake --preset default` for
# build/, a plain Ninja configure otherwise. Every finding is printed once (a header's finding
# once, not once per source including it, with the header's path under src/ rather than the
# build tree's layers/ link), with a count per check; exit 1 on any finding (WarningsAsErrors:
# '*'), or when clang-tidy fails on a file. clang-tidy is the one on PATH ($CLANG_TIDY overrides
# it), installed with apt-get as scripts/deps.sh does when there is none (Debian 12: clang-tidy 14,
# the version the check set is chosen for). Jobs: $KEEL_JOBS, else the number of cores.
# $KEEL_TIDY_DIRS: the top directories whose sources are checked, default every one the build
# compiles, "src tests bench robot examples components" (e.g. KEEL_TIDY_DIRS=src for the
# library alone). fuzz/ is compiled by the asan-ubsan build only: run on build-asan for it.
set -euo pipefail

case "${1:-}" in
  -h|--help) sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
checks=""
if [[ "${1:-}" == --no-analyzer ]]; then
  checks="--checks=-clang-analyzer-*"
  shift
fi
(($# <= 1)) || { echo "usage: scripts/tidy.sh [--no-analyzer] [BUILD_DIR]" >&2; exit 2; }

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_arg=${1:-build}
# A relative BUILD_DIR is taken from where the script is run, else from the repository root.
if [[ "$build_arg" = /* ]]; then
  build=$build_arg
elif [[ -d "$build_arg" ]]; then
  build=$(cd "$build_arg" && pwd)
else
  build=$root/$build_arg
fi

# --- clang-tidy ---------------------------------------------------------------------------
# shellcheck source=lib/tool.sh
source "$root/scripts/lib/tool.sh"
clang_tidy=$(keel_tool tidy.sh clang-tidy "${CLANG_TIDY:-}")
version=$("$clang_tidy" --version | sed -n 's/^ *\(.*version [0-9.]*\).*/\1/p' | head -n 1)
command -v python3 >/dev/null 2>&1 || { echo "tidy.sh: needs python3 (scripts/deps.sh installs it)" >&2; exit 1; }

# --- the compile database -----------------------------------------------------------------
db=$build/compile_commands.json
if [[ ! -f "$db" ]]; then
  command -v cmake >/dev/null 2>&1 || { echo "tidy.sh: no $db and no cmake to write it" >&2; exit 1; }
  if [[ "$build" == "$root/build" ]]; then
    echo "tidy.sh: no $db; configuring (cmake --preset default, no build)" >&2
    (cd "$root" && cmake --preset default >/dev/null)
  else
    echo "tidy.sh: no $db; configuring (cmake -S $root -B $build -G Ninja, no build)" >&2
    cmake -S "$root" -B "$build" -G Ninja >/dev/null
  fi
  [[ -f "$db" ]] || { echo "tidy.sh: configuring did not write $db" >&2; exit 1; }
fi

jobs=${KEEL_JOBS:-$(nproc 2>/dev/null || echo 2)}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
trap 'exit 130' INT TERM  # so that the EXIT trap cleans up

# keel's translation units under $KEEL_TIDY_DIRS, as the database names them, and the database
# as clang reads it: GCC's precompiled header (the tests') is not clang's, so a compile command's
# `-include .../cmake_pch.hxx` becomes the header's text (-Xclang -include: the driver would look
# for the .gch beside it and refuse it).
dirs=${KEEL_TIDY_DIRS:-src tests bench robot examples components}
mkdir -p "$out/db"
# shellcheck disable=SC2086  # the directories, split on purpose
mapfile -d '' files < <(python3 - "$db" "$root" "$out/db/compile_commands.json" $dirs <<'PY'
import json, os, shlex, sys
db, root, clang_db = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3]
dirs = tuple(os.path.join(root, d) + os.sep for d in sys.argv[4:])
seen, entries = set(), []
for entry in json.load(open(db)):
    path = os.path.realpath(os.path.join(entry.get("directory", ""), entry["file"]))
    args = list(entry["arguments"]) if "arguments" in entry else shlex.split(entry["command"])
    clang_args = []
    for i, a in enumerate(args):
        if a == "-include" and i + 1 < len(args) and args[i + 1].endswith("cmake_pch.hxx"):
            clang_args += ["-Xclang", "-include", "-Xclang"]
        else:
            clang_args.append(a)
    entries.append({"directory": entry.get("directory", ""), "file": entry["file"], "arguments": clang_args})
    if path.startswith(dirs) and path.endswith(".cpp") and path not in seen:
        seen.add(path)
json.dump(entries, open(clang_db, "w"))
for path in sorted(seen):
    sys.stdout.write(path + "\0")
PY
)
if ((${#files[@]} == 0)); then
  echo "tidy.sh: $db lists no sources under $dirs of $root (a build tree of another checkout?)" >&2
  exit 1
fi

# A file's result is reused from the cache when everything it depends on is the same
# (scripts/lib/tidy_cache.py: clang-tidy's version, .clang-tidy, these flags, the compile command
# and the preprocessed source with its comments); $KEEL_TIDY_CACHE, else ~/.cache/keel/tidy;
# KEEL_TIDY_CACHE=off runs clang-tidy on every file.
cache=${KEEL_TIDY_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/keel/tidy}
[[ "$cache" == off ]] || "$root/scripts/deps.sh" clang-14  # its preprocessor makes the keys
flags="--quiet --use-color=false --extra-arg=-Wno-unknown-warning-option $checks"
start=$SECONDS
if [[ "$cache" == off ]]; then
  todo=("${files[@]}")
  echo "0 ${#files[@]}" >"$out/hits"
else
  mkdir -p "$cache"
  mapfile -d '' todo < <(KEEL_JOBS=$jobs python3 "$root/scripts/lib/tidy_cache.py" lookup "$out/db/compile_commands.json" "$root" "$build" \
    "$cache" "$out" "$clang_tidy" "$flags" "${files[@]}")
fi
read -r hits _ <"$out/hits"
echo "tidy.sh: $version on ${#files[@]} files of $dirs ($db, -j$jobs${checks:+, without the static analyzer}; $hits from the cache)"
# One output file per translation unit, so that parallel runs never interleave. GCC-only warning
# options in the database (sanitizer presets) are not clang-tidy's business. clang-tidy exits
# non-zero on a finding (WarningsAsErrors) and when it could not compile the file ("Error while
# processing"): only the second is a failure to check it (NAME.failed); NAME.found marks the first.
if ((${#todo[@]} > 0)); then
  printf '%s\0' "${todo[@]}" | xargs -0 -n 1 -P "$jobs" sh -c '
    name=$(printf "%s" "$5" | tr "/" "_")
    if ! "$0" -p "$1" $4 "$5" >"$3/$name.out" 2>"$3/$name.err"; then
      if grep -q "^Error while processing" "$3/$name.err" "$3/$name.out"; then
        echo "$5" >>"$3/$name.failed"
      else
        echo "$5" >>"$3/$name.found"
      fi
    fi' "$clang_tidy" "$out/db" "$root" "$out" "$flags"
fi
[[ "$cache" == off ]] || python3 "$root/scripts/lib/tidy_cache.py" store "$root" "$build" "$cache" "$out"

# Findings, each once, with paths relative to the root and the layers/ links resolved to src/.
python3 - "$out" "$root" "$build" <<'PY'
import collections, glob, os, re, sys
out, root, build = sys.argv[1], sys.argv[2], sys.argv[3]
head = re.compile(r"^(/[^:]+):(\d+):(\d+): (warning|error): (.*?)(?: \[([^\]]+)\])?$")
def rel(path):
    real = os.path.realpath(path)  # build/layers/<layer>/<layer> → src/<layer>
    return os.path.relpath(real, root) if real.startswith(root + os.sep) else real
findings, order = {}, []
for name in sorted(glob.glob(os.path.join(out, "*.out"))):
    block = None
    for line in open(name, errors="replace"):
        line = line.rstrip("\n")
        m = head.match(line)
        if m:
            path, ln, col, _, msg, checks = m.groups()
            checks = [c for c in (checks or "clang-diagnostic").split(",") if c != "-warnings-as-errors"]
            key = (rel(path), int(ln), int(col), msg)
            block = None
            if key not in findings:
                block = findings[key] = {"checks": checks, "lines": []}
                order.append(key)
        elif block is not None and not re.match(r"^\d+ (warnings?|errors?) generated", line):
            block["lines"].append(line)
per_check = collections.Counter()
for key in sorted(order):
    f = findings[key]
    path, ln, col, msg = key
    print(f"{path}:{ln}:{col}: {msg} [{','.join(f['checks'])}]")
    for l in f["lines"]:
        print("    " + l)
    per_check.update(f["checks"])
if per_check:
    print("\nfindings per check:")
    for check, n in per_check.most_common():
        print(f"  {n:4d}  {check}")
open(os.path.join(out, "count"), "w").write(str(len(order)))
PY

count=$(cat "$out/count")
failed=$(cat "$out"/*.failed 2>/dev/null | sort || true)
elapsed=$((SECONDS - start))
if [[ -n "$failed" ]]; then
  # A file clang-tidy could not check is a failure, findings elsewhere or not: show what it said.
  for f in $failed; do
    name=$(printf '%s' "$f" | tr '/' '_')
    echo "tidy.sh: clang-tidy failed on ${f#"$root"/}:" >&2
    grep -v -E '^[0-9]+ warnings? generated|^Suppressed [0-9]+ warnings|^Use -header-filter|^Use -system-headers' \
      "$out/$name.err" | sed 's/^/    /' >&2 || true
  done
  echo "tidy.sh: failed ($version, ${elapsed} s)" >&2
  exit 1
fi
if ((count > 0)); then
  echo "tidy.sh: $count finding(s) in ${#files[@]} files ($version, ${elapsed} s)" >&2
  exit 1
fi
echo "tidy.sh: no findings in ${#files[@]} files ($version, ${elapsed} s, $hits from the cache)"
