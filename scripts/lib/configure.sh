#!/usr/bin/env bash
# Configures the build directory of a CMake preset: `scripts/lib/configure.sh PRESET [ARGS...]`
# runs `cmake --preset PRESET ARGS...`, after starting the directory's CMake cache afresh when it
# was configured with another compiler than the preset names (CMake cannot change the compiler
# of a configured build: build-asan/ was GCC's before it became clang's). The objects stay; ccache
# serves those that did not change.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
preset=$1
shift
read -r dir compiler < <(python3 - "$preset" <<'PY'
import json, sys
presets = {p["name"]: p for p in json.load(open("CMakePresets.json"))["configurePresets"]}
p = presets[sys.argv[1]]
print(p["binaryDir"].replace("${sourceDir}/", ""), p.get("cacheVariables", {}).get("CMAKE_CXX_COMPILER", "-"))
PY
)
cache=$dir/CMakeCache.txt
if [[ $compiler != - && -f $cache ]]; then
  configured=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$cache")
  if [[ -n $configured && $(basename "$configured") != "$compiler" ]]; then
    echo "configure.sh: $dir/ was configured with $(basename "$configured"), the $preset preset uses $compiler: configuring it afresh"
    rm -rf "$cache" "$dir/CMakeFiles"
  fi
fi
exec cmake --preset "$preset" "$@"
