#!/usr/bin/env bash
# Formats keel's C++ with clang-format and the style in .clang-format
# (docs/decisions/0008-format-and-lint.md).
#
#   scripts/format.sh           reformat every C++ file keel owns, in place
#   scripts/format.sh --check   change nothing; exit 1 listing the files that are not formatted (CI)
#                               (exit 2: clang-format itself failed or cannot read .clang-format)
#
# The files are git's (tracked, plus new files not yet added; *.cpp *.hpp *.h), less the
# third-party paths below. clang-format is the one found on PATH ($CLANG_FORMAT overrides it);
# when there is none, Debian 12's (clang-format 14, the version the style is checked with) is
# installed with apt-get, as scripts/deps.sh does. Different clang-format versions format a few
# constructs differently, so a --check failure names the version it used.
set -euo pipefail

usage() { echo "usage: scripts/format.sh [--check]" >&2; exit 2; }
check=0
case "${1:-}" in
  "") ;;
  --check) check=1 ;;
  -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) usage ;;
esac
(($# <= 1)) || usage

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

# Paths keel does not own and never reformats (none today; add vendored code here).
third_party_re='^(third_party|external|vendor)/'

# --- the clang-format to use -------------------------------------------------------------
# shellcheck source=lib/tool.sh
source "$root/scripts/lib/tool.sh"
# Pinned: every file below is formatted by this one binary.
clang_format=$(keel_tool format.sh clang-format "${CLANG_FORMAT:-}")
version=$("$clang_format" --version)
# An option this clang-format does not know would otherwise show up as "every file unformatted".
if ! err=$("$clang_format" --style=file --dump-config 2>&1 >/dev/null); then
  printf 'format.sh: %s cannot read .clang-format:\n%s\n' "$version" "$err" >&2
  exit 2
fi

# --- the files -----------------------------------------------------------------------------
files=()
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  while IFS= read -r -d '' f; do
    [[ -f "$f" ]] || continue  # deleted in the work tree, not yet in the index
    [[ "$f" =~ $third_party_re ]] && continue
    files+=("$f")
  done < <(git ls-files -z --cached --others --exclude-standard -- '*.cpp' '*.hpp' '*.h' | sort -zu)
else
  # A source tarball: every C++ file outside build trees.
  while IFS= read -r -d '' f; do
    f=${f#./}
    [[ "$f" =~ $third_party_re ]] && continue
    files+=("$f")
  done < <(find . \( -path './build*' -o -path './.git' -o -path './out' \) -prune -o \
                \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -type f -print0 | sort -z)
fi
((${#files[@]} > 0)) || { echo "format.sh: no C++ files found under $root" >&2; exit 1; }

jobs=$(nproc 2>/dev/null || echo 2)

if ((check == 0)); then
  if ! printf '%s\0' "${files[@]}" | xargs -0 -n 16 -P "$jobs" "$clang_format" -i --style=file; then
    echo "format.sh: $clang_format failed" >&2
    exit 2
  fi
  echo "format.sh: formatted ${#files[@]} files with $version"
  exit 0
fi

# --check: a file is formatted when clang-format would change nothing in it. With --dry-run
# -Werror it names each such file in "FILE:LINE:COL: error: code should be clang-formatted"
# (one process at a time, so that the reports do not interleave; it takes a second or two).
set +e
report=$(printf '%s\0' "${files[@]}" | xargs -0 -n 64 "$clang_format" --dry-run -Werror --style=file 2>&1)
status=$?
set -e
if ((status != 0 && status != 123)); then  # 123: some file not formatted; anything else: a crash
  printf '%s\n' "$report" | tail -n 20 >&2
  echo "format.sh: $clang_format failed (xargs status $status)" >&2
  exit 2
fi
bad=$(printf '%s\n' "$report" | sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' | sort -u)
if ((status == 123)) && [[ -z "$bad" ]]; then
  printf '%s\n' "$report" | tail -n 20 >&2
  echo "format.sh: $clang_format failed" >&2
  exit 2
fi
if [[ -n "$bad" ]]; then
  n=$(printf '%s\n' "$bad" | wc -l)
  echo "format.sh: $n of ${#files[@]} files are not formatted ($version, $clang_format):" >&2
  printf '%s\n' "$bad" | sed 's/^/  /' >&2
  echo "format.sh: run scripts/format.sh to format them (with the same clang-format major version)" >&2
  major=$(printf '%s\n' "$version" | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
  if [[ "$major" != 14 ]]; then
    echo "format.sh: note: the tree is formatted with clang-format 14 (Debian 12); $major may lay out some code differently" >&2
  fi
  exit 1
fi
echo "format.sh: ${#files[@]} files formatted ($version)"
