#!/usr/bin/env python3
"""scripts/deps.sh as a new user meets it: quiet when everything is installed, one line when it
installs (apt's output in a log), and apt's own words when apt fails.

apt-get, dpkg-query and id are stand-ins on PATH: the test installs nothing. The stand-in
apt-get prints 300 lines, as the real one does on a fresh machine."""
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEPS = ROOT / "scripts" / "deps.sh"


def stand_ins(bin_dir: pathlib.Path, installed: bool, apt_fails: bool) -> None:
    status = "install ok installed" if installed else "unknown ok not-installed"
    tools = {
        "dpkg-query": f"#!/bin/sh\nprintf '%s' '{status}'\n",
        "id": "#!/bin/sh\necho 0\n",
        "apt-get": (
            "#!/bin/sh\n"
            'echo "$*" >> "$APT_CALLS"\n'
            "i=0; while [ $i -lt 300 ]; do echo \"Get:$i http://deb.debian.org bookworm/main\"; i=$((i+1)); done\n"
            + ('case "$*" in *install*) echo "E: Unable to locate package erlang-base" >&2; exit 100;; esac\n'
               if apt_fails else "")
            + "exit 0\n"),
    }
    for name, text in tools.items():
        path = bin_dir / name
        path.write_text(text)
        path.chmod(0o755)


def run(installed: bool, apt_fails: bool = False):
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        bin_dir = tmp / "bin"
        bin_dir.mkdir()
        stand_ins(bin_dir, installed, apt_fails)
        calls = tmp / "apt_calls"
        env = dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}", TMPDIR=str(tmp), APT_CALLS=str(calls))
        r = subprocess.run(["bash", str(DEPS)], env=env, capture_output=True, text=True, timeout=60)
        apt = calls.read_text().splitlines() if calls.exists() else []
        log = (tmp / "keel-deps.log").read_text() if (tmp / "keel-deps.log").exists() else ""
        return r, apt, log


def check(cond: bool, what: str, failures: list) -> None:
    if not cond:
        failures.append(what)


def main() -> int:
    failures = []

    r, apt, _ = run(installed=True)
    check(r.returncode == 0, f"all installed: exit {r.returncode}", failures)
    check(r.stdout == "" and r.stderr == "", f"all installed: printed {r.stdout!r} {r.stderr!r}", failures)
    check(apt == [], f"all installed: apt-get ran: {apt}", failures)

    r, apt, log = run(installed=False)
    lines = (r.stdout + r.stderr).splitlines()
    check(r.returncode == 0, f"installing: exit {r.returncode}: {r.stderr}", failures)
    check(len(lines) == 1, f"installing: {len(lines)} lines on the screen, not one:\n" + "\n".join(lines[:5]),
          failures)
    check(bool(lines) and lines[0].startswith("deps.sh: installing ") and "keel-deps.log" in lines[0],
          f"installing: the line says neither what nor where the log is: {lines[:1]}", failures)
    check(len(apt) == 2 and apt[0].startswith("update") and apt[1].startswith("install -y"),
          f"installing: apt-get calls {apt}", failures)
    check(log.count("Get:") == 600, "installing: apt's output is not in the log", failures)

    r, apt, _ = run(installed=False, apt_fails=True)
    check(r.returncode != 0, "apt failing: deps.sh succeeded", failures)
    check("E: Unable to locate package erlang-base" in r.stderr, f"apt failing: apt's error not shown: {r.stderr!r}",
          failures)
    check(len(r.stdout.splitlines()) == 1, f"apt failing: stdout {r.stdout!r}", failures)

    for f in failures:
        print("FAIL:", f if len(f) < 400 else f[:400] + " ...")
    print("deps_test:", "passed" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
