# Sourced by scripts/format.sh and scripts/tidy.sh: finds a tool keel's scripts run, installing
# Debian's package of the same name with apt-get when it is missing (as scripts/deps.sh does).
#
#   keel_tool SCRIPT COMMAND [PATH]   prints COMMAND's absolute path; PATH, when given and not
#                                     empty, is used instead of searching (the $CLANG_* override)
# Exits the calling script with 1 when the tool cannot be had; messages start with "SCRIPT:".

keel_tool() {
  local script=$1 cmd=$2 chosen=${3:-}
  if [[ -z "$chosen" ]]; then
    chosen=$(command -v "$cmd" || true)
    if [[ -z "$chosen" ]]; then
      keel_install_package "$script" "$cmd"
      chosen=$(command -v "$cmd" || true)
      [[ -n "$chosen" ]] || { echo "$script: $cmd still not found after installing" >&2; exit 1; }
    fi
  fi
  local path
  path=$(command -v "$chosen" || true)
  [[ -n "$path" && -x "$path" ]] || { echo "$script: $chosen is not an executable" >&2; exit 1; }
  printf '%s\n' "$path"
}

# keel_install_package SCRIPT PACKAGE: apt-get install, as root or through sudo.
keel_install_package() {
  local script=$1 package=$2
  if ! command -v apt-get >/dev/null 2>&1 || ! command -v dpkg-query >/dev/null 2>&1; then
    echo "$script: no $package and not a Debian system; install $package (14) yourself" >&2
    exit 1
  fi
  local as_root=()
  if [[ $(id -u) -ne 0 ]]; then
    if command -v sudo >/dev/null 2>&1; then
      as_root=(sudo)
    else
      echo "$script: need root to install $package (run as root, or install sudo)" >&2
      exit 1
    fi
  fi
  echo "$script: installing $package" >&2
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq >&2
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -qq --no-install-recommends "$package" >/dev/null
}
