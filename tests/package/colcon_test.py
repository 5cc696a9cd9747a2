#!/usr/bin/env python3
"""keel in a ROS 2 workspace, built by colcon as PyPI ships it (colcon-common-extensions).

1. A workspace in a temporary folder: src/keel, a copy of keel's source tree as a clone holds it
   (no build trees), and src/hello_keel (tests/package/colcon/hello_keel), a package of two
   components whose package.xml depends on keel and whose CMakeLists.txt calls
   find_package(keel REQUIRED) and keel_add_component().
2. `colcon list` identifies both as `ros.cmake` packages (colcon-ros reading package.xml through
   catkin_pkg, build type cmake), and `colcon info keel` gives package.xml's version, which must
   be the CMake project's.
3. `colcon build` builds both. hello_keel sorts before keel and colcon runs one package at a
   time here, so only keel's declared dependency puts keel first: its `Finished <<< keel` comes
   before `Starting >>> hello_keel`. hello_keel found keel's CMake package in keel's install
   space (keel_DIR in its cache), put on CMAKE_PREFIX_PATH by colcon, not elsewhere.
4. In a shell that sourced install/setup.bash: `keel` on PATH is install/keel/bin/keel;
   `keel --version` says the CMake project's version; `keel inspect` of hello_keel's installed
   library lists both components and their ports; `keel run` of its installed application (the
   library found through KEEL_COMPONENT_PATH) reaches Active and ends Destroyed without a fault.

keel is built as a workspace builds it, with a user's options (no -Werror), but without its
tests, benchmarks and examples (KEEL_BUILD_TESTS, KEEL_BUILD_BENCH, KEEL_BUILD_EXAMPLES off, in
the workspace's colcon.meta): the rest of the suite builds and runs those, and they would make
this test's build twice as long (356 compiles, not 186). It compiles through keel's ccache
(KEEL_CCACHE), whose base_dir is the workspace's root (KEEL_CCACHE_BASEDIR) so that a later
run, in another temporary folder, takes its objects from the cache (it prints how many did);
at most KEEL_JOBS (2) compiles at once (Ninja's job pools: colcon asks Ninja for one job per
CPU).

Exits 77 (skipped) when the peers' venv or its colcon is missing (scripts/peers.sh installs
them); otherwise non-zero, naming the step and showing the output, on any failure, and keeps
the workspace then. Called by CTest (tests/package/CMakeLists.txt); runnable by hand with the
same arguments.
"""
import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from package_test import Failure, check_log, expect, run  # noqa: E402

COMPONENTS = {"Talker": ["said"], "Listener": ["heard"]}
# What a clone has and a build adds, left out of the copy: build trees (the checkout's own
# build*/ and demo/ at its root), and what scripts/peers.sh installs.
LEFT_OUT = {".git", "venv", "node_modules", "__pycache__"}
LEFT_OUT_AT_ROOT = ("build", "demo", "out")


def copy_source(source, to):
    def ignore(directory, names):
        at_root = Path(directory).resolve() == source.resolve()
        return [n for n in names if n in LEFT_OUT or (at_root and n.startswith(LEFT_OUT_AT_ROOT))]
    shutil.copytree(source, to, ignore=ignore, symlinks=True)


def make_workspace(args, ws):
    copy_source(args.keel_source, ws / "src" / "keel")
    shutil.copytree(args.user_package, ws / "src" / "hello_keel")
    pools = [f"-DCMAKE_JOB_POOLS=compile={args.jobs}", "-DCMAKE_JOB_POOL_COMPILE=compile",
             "-DCMAKE_JOB_POOL_LINK=compile", "-G", "Ninja"]
    keel = ["-DKEEL_BUILD_TESTS=OFF", "-DKEEL_BUILD_BENCH=OFF", "-DKEEL_BUILD_EXAMPLES=OFF",
            "-DKEEL_CCACHE=ON", f"-DKEEL_CCACHE_BASEDIR={ws}"]
    meta = {"names": {"keel": {"cmake-args": pools + keel}, "hello_keel": {"cmake-args": pools}}}
    (ws / "colcon.meta").write_text(json.dumps(meta, indent=2) + "\n")


def environment(ws):
    """This environment without what would find a keel, or colcon settings, from elsewhere."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("CMAKE_PREFIX_PATH", "AMENT_PREFIX_PATH", "COLCON_PREFIX_PATH", "KEEL_COMPONENT_PATH",
                        "COLCON_DEFAULTS_FILE", "MAKEFLAGS")}
    env["COLCON_HOME"] = str(ws / "colcon-home")  # no user's defaults.yaml or mixins
    env["CCACHE_STATSLOG"] = str(ws / "ccache-stats.log")  # what each compile through ccache did
    return env


def check_list(colcon, ws, env, version):
    out = run("colcon list", [colcon, "list"], cwd=ws, env=env)
    found = {}
    for line in out.splitlines():
        fields = line.split("\t")
        if len(fields) == 3:
            found[fields[0]] = (fields[1], fields[2])
    expect(found.get("keel") == ("src/keel", "(ros.cmake)"),
           f"colcon list: keel is not a ros.cmake package at src/keel:\n{out}")
    expect(found.get("hello_keel") == ("src/hello_keel", "(ros.cmake)"),
           f"colcon list: hello_keel is not a ros.cmake package at src/hello_keel:\n{out}")
    expect(len(found) == 2, f"colcon list: packages other than keel and hello_keel (colcon went into keel's "
           f"tree?):\n{out}")
    out = run("colcon info keel", [colcon, "info", "keel"], cwd=ws, env=env)
    expect(f"version: {version}\n" in out,
           f"colcon info keel: package.xml's version is not the CMake project's {version}:\n{out}")


def last_lines(path, count=60):
    try:
        return "\n".join(path.read_text(errors="replace").splitlines()[-count:])
    except OSError:
        return f"(no {path})"


def build(colcon, ws, env, timeout):
    cmd = [colcon, "build", "--parallel-workers", "1", "--metas", ws / "colcon.meta",
           "--event-handlers", "status-", "desktop_notification-", "terminal_title-"]
    try:
        out = run("colcon build", cmd, cwd=ws, env=env, timeout=timeout)
    except Failure as e:
        logs = sorted((ws / "log" / "latest_build").glob("*/stdout_stderr.log"))
        raise Failure(f"{e}\n" + "\n".join(f"--- the end of {log}:\n{last_lines(log)}" for log in logs))
    finished = out.find("Finished <<< keel")
    started = out.find("Starting >>> hello_keel")
    expect(finished >= 0 and started > finished,
           f"colcon build: hello_keel was not built after keel had finished:\n{out}")
    cache = (ws / "build" / "hello_keel" / "CMakeCache.txt").read_text()
    keel_dir = next((l.split("=", 1)[1] for l in cache.splitlines() if l.startswith("keel_DIR:")), "")
    wanted = ws / "install" / "keel" / "lib" / "cmake" / "keel"
    expect(keel_dir and Path(keel_dir).resolve() == wanted.resolve(),
           f"hello_keel: find_package(keel) found '{keel_dir}', not {wanted}")
    return out


def check_ccache(ws):
    """keel compiled through ccache, base_dir the workspace: ccache's log of this build's compiles
    (CCACHE_STATSLOG) says how many, and how many came from the cache."""
    rules = (ws / "build" / "keel" / "CMakeFiles" / "rules.ninja").read_text()
    expect(f"CCACHE_BASEDIR={ws} " in rules, f"keel: ccache's base_dir is not the workspace {ws}")
    records = (ws / "ccache-stats.log").read_text().split("# ")[1:] if (ws / "ccache-stats.log").exists() else []
    expect(records, "keel: no compile went through ccache (KEEL_CCACHE)")
    hits = sum(1 for r in records if "direct_cache_hit" in r or "preprocessed_cache_hit" in r)
    print(f"-- keel: {len(records)} compiles through ccache, {hits} from the cache", flush=True)


def sourced(ws, env, step, command, timeout=120):
    """Runs a bash command line after sourcing the workspace's install/setup.bash."""
    return run(step, ["bash", "-c", f'source install/setup.bash && {command}'], cwd=ws, env=env, timeout=timeout)


def check_installed(ws, env, version):
    keel = ws / "install" / "keel" / "bin" / "keel"
    found = sourced(ws, env, "keel on PATH", "command -v keel").strip()
    expect(found and Path(found).resolve() == keel.resolve(), f"keel on PATH is '{found}', not {keel}")
    out = sourced(ws, env, "keel --version", "keel --version")
    expect(out == f"keel {version}\n", f"keel --version: said {out!r}, want 'keel {version}'")
    lib = ws / "install" / "hello_keel" / "lib" / "keel" / "libhello_keel.so"
    expect(lib.exists(), f"hello_keel: {lib} not installed")
    out = sourced(ws, env, "keel inspect", f"keel inspect '{lib}'")
    for component, ports in COMPONENTS.items():
        expect(f"\n{component}\n" in f"\n{out}", f"keel inspect: component {component} not listed:\n{out}")
        for port in ports:
            expect(port in out, f"keel inspect: port {component}.{port} not listed:\n{out}")
    app = ws / "install" / "hello_keel" / "share" / "hello_keel" / "app.xml"
    log = ws / "run.jsonl"
    sourced(ws, env, "keel run",
            f"KEEL_COMPONENT_PATH='{lib.parent}' keel run '{app}' --duration 1 --log '{log}'")
    check_log(log, ["talker", "listener"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--colcon", required=True, type=Path, help="the peers' venv's colcon")
    parser.add_argument("--keel-source", required=True, type=Path, help="keel's source tree")
    parser.add_argument("--user-package", required=True, type=Path, help="tests/package/colcon/hello_keel")
    parser.add_argument("--version", required=True, help="the CMake project's version")
    parser.add_argument("--jobs", type=int, default=int(os.environ.get("KEEL_JOBS", "2")))
    parser.add_argument("--timeout", type=int, default=1500, help="seconds colcon build may take")
    args = parser.parse_args()

    if not os.access(args.colcon, os.X_OK):
        print(f"colcon_test: needs colcon in the peers' venv ({args.colcon}; scripts/peers.sh installs it); "
              "skipped", flush=True)
        return 77
    ws = Path(tempfile.mkdtemp(prefix="keel-colcon-")).resolve()
    env = environment(ws)
    started = time.monotonic()
    try:
        make_workspace(args, ws)
        check_list(args.colcon, ws, env, args.version)
        t = time.monotonic()
        build(args.colcon, ws, env, args.timeout)
        print(f"-- colcon build took {time.monotonic() - t:.0f} s", flush=True)
        check_ccache(ws)
        check_installed(ws, env, args.version)
    except Failure as e:
        print(f"FAILED: {e}\n(the workspace is kept: {ws})", file=sys.stderr, flush=True)
        return 1
    shutil.rmtree(ws, ignore_errors=True)
    print(f"-- colcon test passed in {time.monotonic() - started:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
