#!/usr/bin/env python3
"""What an outside component author does with an installed keel, end to end.

1. `cmake --install <keel build> --prefix <work>/staged`, then move the tree to <work>/prefix
   (the install must be relocatable), and check its layout, RUNPATHs and CMake package; the
   installed keel inspects its own component libraries and validates its own profiles.
2. Configure and build tests/package/project (two components in one library) with
   CMAKE_PREFIX_PATH=<prefix>: find_package(keel) and keel_add_component().
3. `<prefix>/bin/keel inspect libgreeters.so` lists both components and their ports.
4. `<prefix>/bin/keel run app.xml --duration 1 --log run.jsonl` in the project's build dir;
   the log shows both instances reaching Active and then Destroyed, and no fault. The project's
   OPRoS component (keel_add_opros_component, libShouter.so) is an OPRoS library to `keel
   inspect`, and in app_opros.xml hears the Greeter.
   The project's messages (keel_add_messages, greeters_msgs/msg/*.msg with a field of keel's
   std_msgs/Header) are built into libannouncer.so, whose port `keel inspect` shows under its
   ROS 2 type name.
5. `cmake --install` of the project puts libgreeters.so into <prefix>/lib/keel; the same
   application run from the installed profiles finds it there, through libkeel's location.
6. The installed robot: `<prefix>/bin/keel run <prefix>/share/keel/robot/navigation.xml` with
   the installed segfault scenario, from elsewhere: keel finds the robot's library, its motion
   board program and keel-host through its own location; both faults are detected and
   recovered, every component ends Destroyed, and nothing keel started is left running.

Exits non-zero, naming the step and showing the command's output, on any failure.
Called by CTest (tests/package/CMakeLists.txt); runnable by hand with the same arguments.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

COMPONENTS = {"Greeter": ["greeting"], "Counter": ["greetings", "count"]}
INSTANCES = ["greeter", "counter"]


class Failure(Exception):
    pass


def run(step, cmd, cwd=None, timeout=600, env=None):
    """Runs cmd (in env, else this environment); returns its combined output, raises Failure
    with it on a non-zero exit."""
    printable = " ".join(str(c) for c in cmd)
    print(f"-- {step}: {printable}", flush=True)
    try:
        proc = subprocess.run([str(c) for c in cmd], cwd=cwd, stdin=subprocess.DEVNULL,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=timeout, env=env)
    except subprocess.TimeoutExpired as e:
        raise Failure(f"{step}: timed out after {timeout} s\n$ {printable}\n{e.output or ''}")
    except OSError as e:
        raise Failure(f"{step}: cannot run: {e}\n$ {printable}")
    if proc.returncode != 0:
        raise Failure(f"{step}: exit code {proc.returncode}\n$ {printable}\n{proc.stdout}")
    return proc.stdout


def expect(condition, message):
    if not condition:
        raise Failure(message)


def install_keel(args, work):
    staged, prefix = work / "staged", work / "prefix"
    cmd = [args.cmake, "--install", args.keel_build, "--prefix", staged]
    if args.config:
        cmd += ["--config", args.config]
    run("install keel", cmd)
    staged.rename(prefix)  # relocation: nothing may point into the staged path
    return prefix, staged


def find_libdir(prefix):
    found = sorted(prefix.glob("lib*/**/libkeel.so"))
    expect(found, f"install layout: no libkeel.so under {prefix}/lib*")
    return found[0].parent


def check_layout(prefix, libdir):
    cmakedir = libdir / "cmake" / "keel"
    wanted = [prefix / "bin" / "keel", prefix / "include" / "keel" / "component.hpp",
              prefix / "include" / "keel" / "keel.hpp"]
    wanted += [cmakedir / f for f in ("keelConfig.cmake", "keelConfigVersion.cmake",
                                      "keelTargets.cmake", "KeelComponent.cmake")]
    for path in wanted:
        expect(path.exists(), f"install layout: missing {path}")
    expect(os.access(prefix / "bin" / "keel", os.X_OK), "install layout: bin/keel not executable")
    expect(list(libdir.glob("libkeel.so.*")), f"install layout: no libkeel.so.<version> in {libdir}")
    return cmakedir


def mentions(text, path):
    """True if `text` names `path` (or something under it) as a whole path."""
    return re.search(r"(?<![\w.-])" + re.escape(str(path)) + r"(?![\w.-])", text) is not None


def check_no_absolute_paths(cmakedir, forbidden):
    for f in sorted(cmakedir.glob("*.cmake")):
        text = f.read_text(errors="replace")
        for path in forbidden:
            expect(not mentions(text, path), f"relocatable install: {f} mentions '{path}'")


def runpath(readelf, binary):
    out = run(f"read RUNPATH of {binary.name}", [readelf, "-d", binary])
    for line in out.splitlines():
        if "(RUNPATH)" in line or "(RPATH)" in line:
            return line.split("[", 1)[1].rsplit("]", 1)[0]
    return ""


def check_runpaths(prefix, libdir):
    """Every RUNPATH is $ORIGIN-relative; bin/keel's leads to the installed libkeel."""
    readelf = shutil.which("readelf")
    if not readelf:
        print("-- RUNPATH check skipped: readelf not found", flush=True)
        return
    keel = prefix / "bin" / "keel"
    binaries = [keel, libdir / "libkeel.so"] + sorted((libdir / "keel").glob("*.so"))
    for binary in binaries:
        rp = runpath(readelf, binary.resolve())
        for entry in filter(None, rp.split(":")):
            expect(entry.startswith("$ORIGIN"),
                   f"relocatable install: {binary} has RUNPATH entry '{entry}' (want $ORIGIN...)")
    dirs = [Path(e.replace("$ORIGIN", str(keel.parent))).resolve()
            for e in runpath(readelf, keel).split(":") if e]
    expect(libdir.resolve() in dirs, f"bin/keel: RUNPATH {dirs} does not lead to {libdir}")


def build_project(args, work, prefix, cmakedir):
    build = work / "project-build"
    cmd = [args.cmake, "-S", args.project, "-B", build, "-G", args.generator,
           f"-DCMAKE_PREFIX_PATH={prefix}", f"-DCMAKE_INSTALL_PREFIX={prefix}",
           "-DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF"]
    for var, value in (("CMAKE_CXX_COMPILER", args.cxx_compiler),
                       ("CMAKE_MAKE_PROGRAM", args.make_program),
                       ("CMAKE_BUILD_TYPE", args.build_type),
                       ("CMAKE_CXX_FLAGS", args.cxx_flags)):
        if value:
            cmd.append(f"-D{var}={value}")
    run("configure the component project", cmd)
    cache = (build / "CMakeCache.txt").read_text()
    keel_dir = next((l.split("=", 1)[1] for l in cache.splitlines() if l.startswith("keel_DIR:")), "")
    expect(keel_dir and Path(keel_dir).resolve() == cmakedir.resolve(),
           f"find_package(keel) found '{keel_dir}', not the installed {cmakedir}")
    cmd = [args.cmake, "--build", build, "--parallel", "2"]
    if args.config:
        cmd += ["--config", args.config]
    run("build the component project", cmd)
    libs = sorted(build.rglob("libgreeters.so"))
    expect(libs, f"keel_add_component: no libgreeters.so under {build}")
    expect(libs[0].parent == build or args.config,
           f"keel_add_component: library built in {libs[0].parent}, not the author's build dir")
    return build, libs[0]


def check_inspect(keel, lib):
    out = run("keel inspect", [keel, "inspect", lib], timeout=60)
    for component, ports in COMPONENTS.items():
        expect(component in out, f"keel inspect {lib.name}: component {component} not listed:\n{out}")
        for port in ports:
            expect(port in out, f"keel inspect {lib.name}: port {component}.{port} not listed:\n{out}")


def check_shipped(keel, prefix, libdir):
    """keel's own component libraries and profiles, as installed, are usable."""
    for lib in sorted((libdir / "keel").glob("*.so")):
        out = run(f"keel inspect {lib.name}", [keel, "inspect", lib], timeout=60)
        expect("component" in out, f"keel inspect {lib}: lists no component:\n{out}")
    # Fault scenarios are not profiles: the robot's run below loads one.
    profiles = sorted(p for p in (prefix / "share" / "keel").rglob("*.xml") if "scenarios" not in p.parts)
    if profiles:
        run("keel validate the installed profiles", [keel, "validate", *profiles], timeout=60)


def check_log(log, instances=INSTANCES):
    expect(log.exists(), f"keel run: no log written at {log}")
    states = {name: [] for name in instances}
    faults = []
    for number, line in enumerate(log.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
        except json.JSONDecodeError as e:
            raise Failure(f"{log}:{number}: not JSON ({e}): {line}")
        expect(isinstance(record, dict) and "event" in record and "t_ns" in record,
               f"{log}:{number}: a record needs 'event' and 't_ns': {line}")
        if record["event"] == "state" and record.get("component") in states:
            states[record["component"]].append(record.get("to", record.get("state")))
        elif record["event"] == "detected":
            faults.append(line)
    expect(not faults, f"{log}: faults were detected:\n" + "\n".join(faults))
    for name, seen in states.items():
        expect("Active" in seen, f"{log}: '{name}' never reached Active (states: {seen})")
        expect(seen and seen[-1] == "Destroyed" and seen.index("Active") < len(seen) - 1,
               f"{log}: '{name}' did not end Destroyed after Active (states: {seen})")


def check_run(keel, profile, cwd, log):
    run(f"keel run {profile}", [keel, "run", profile, "--duration", "1", "--log", log],
        cwd=cwd, timeout=120)
    check_log(cwd / log)  # `log` may be relative to cwd or absolute


def check_opros(keel, build):
    """The OPRoS component: keel_add_opros_component built libShouter.so against the installed
    OPRoS headers and libkeel_opros; keel inspect knows it, and it hears the Greeter."""
    lib = build / "libShouter.so"
    expect(lib.exists(), f"keel_add_opros_component: no libShouter.so in {build}")
    out = run("keel inspect libShouter.so", [keel, "inspect", lib], timeout=60)
    expect("an OPRoS component library" in out and "greetings" in out,
           f"keel inspect libShouter.so: not shown as an OPRoS library with its port:\n{out}")
    out = run("keel run app_opros.xml", [keel, "run", "app_opros.xml", "--duration", "1", "--log", "opros.jsonl"],
              cwd=build, timeout=120)
    expect("shouter heard " in out, f"keel run app_opros.xml: the OPRoS component heard nothing:\n{out}")
    check_log(build / "opros.jsonl", ["greeter", "shouter"])


def check_messages(keel, prefix, build):
    """keel_add_messages from the installed package: the project's messages, generated against the
    installed shipped ones, compile into a component library that loads (their DDS registrations
    find libkeel's) and whose ports carry them under their ROS 2 names."""
    for path in (prefix / "share" / "keel" / "msgs" / "std_msgs" / "msg" / "Header.msg",
                 prefix / "share" / "keel" / "idl" / "std_msgs" / "msg" / "Header_.idl",
                 prefix / "include" / "keel" / "msg" / "std_msgs" / "msg" / "header.hpp",
                 prefix / "include" / "keel" / "idlc" / "std_msgs" / "msg" / "Header_.h"):
        expect(path.exists(), f"install layout: missing {path}")
    lib = build / "libannouncer.so"
    expect(lib.exists(), f"keel_add_messages: no libannouncer.so in {build}")
    header = next(build.rglob("greeting.hpp"), None)
    expect(header is not None and "struct Greeting {" in header.read_text(),
           f"keel_add_messages: no keel/msg/greeters_msgs/msg/greeting.hpp under {build}")
    out = run("keel inspect libannouncer.so", [keel, "inspect", lib], timeout=60)
    expect("greeters_msgs/msg/Greeting" in out and "std_msgs/msg/Float64" in out,
           f"keel inspect libannouncer.so: ports not shown with their ROS 2 types:\n{out}")


def check_installed_run(args, work, prefix, libdir, build):
    run("install the component project", [args.cmake, "--install", build]
        + (["--config", args.config] if args.config else []))
    expect((libdir / "keel" / "libgreeters.so").exists(),
           f"keel_add_component(INSTALL): libgreeters.so not installed into {libdir / 'keel'}")
    profile = prefix / "share" / "greeters" / "app.xml"
    expect(profile.exists(), f"component project: {profile} not installed")
    elsewhere = work / "elsewhere"
    elsewhere.mkdir()
    check_run(prefix / "bin" / "keel", profile, elsewhere, elsewhere / "installed-run.jsonl")


def check_installed_robot(work, prefix):
    robot = prefix / "share" / "keel" / "robot"
    for path in (robot / "navigation.xml", robot / "scenarios" / "segfault.xml", prefix / "bin" / "keel_motion_board"):
        expect(path.exists(), f"installed robot: missing {path}")
    elsewhere = work / "robot-run"
    elsewhere.mkdir()
    log = elsewhere / "robot.jsonl"
    out = run("keel run the installed robot", [prefix / "bin" / "keel", "run", robot / "navigation.xml",
                                               "--inject", robot / "scenarios" / "segfault.xml",
                                               "--duration", "6", "--log", log], cwd=elsewhere, timeout=120)
    records = [json.loads(line) for line in log.read_text().splitlines() if line.strip()]
    # The scenario's two signals, once each (a busy machine may add a late cycle's heartbeat).
    signals = sorted(r["component"] for r in records if r["event"] == "detected" and r["kind"] == "signal")
    recovered = {r["component"] for r in records if r["event"] == "recovered"}
    expect(signals == ["detector", "planner"], f"installed robot: signals of {signals}, want the scenario's two\n{out}")
    expect({"detector", "planner"} <= recovered, f"installed robot: recovered {recovered}\n{out}")
    last = {}
    for r in records:
        if r["event"] == "state":
            last[r["component"]] = r["to"]
    expect(len(last) >= 14 and all(s == "Destroyed" for s in last.values()),
           f"installed robot: not every component ended Destroyed: {last}")
    left = run("list processes", ["ps", "-eo", "args"])
    for program in ("keel_motion_board", "keel-host"):
        expect(not any(line.startswith(str(prefix / "bin" / program)) for line in left.splitlines()),
               f"installed robot: {program} still running after keel run ended")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cmake", required=True)
    parser.add_argument("--keel-build", required=True, type=Path, help="keel's build tree")
    parser.add_argument("--keel-source", required=True, type=Path, help="keel's source tree")
    parser.add_argument("--project", required=True, type=Path, help="the component project")
    parser.add_argument("--work", required=True, type=Path, help="scratch dir (wiped)")
    parser.add_argument("--generator", required=True)
    parser.add_argument("--make-program", default="")
    parser.add_argument("--cxx-compiler", default="")
    parser.add_argument("--cxx-flags", default="")
    parser.add_argument("--build-type", default="")
    parser.add_argument("--config", default="", help="configuration (multi-config generators)")
    args = parser.parse_args()

    os.environ.pop("KEEL_COMPONENT_PATH", None)  # keel must find its libraries unaided
    work = args.work.resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    try:
        prefix, staged = install_keel(args, work)
        libdir = find_libdir(prefix)
        cmakedir = check_layout(prefix, libdir)
        forbidden = [args.keel_build.resolve(), args.keel_source.resolve(), staged]
        check_no_absolute_paths(cmakedir, forbidden)
        check_runpaths(prefix, libdir)
        keel = prefix / "bin" / "keel"
        check_shipped(keel, prefix, libdir)
        build, lib = build_project(args, work, prefix, cmakedir)
        check_inspect(keel, lib)
        check_run(keel, "app.xml", lib.parent, "run.jsonl")
        check_opros(keel, lib.parent)
        check_messages(keel, prefix, build)
        check_installed_run(args, work, prefix, libdir, build)
        check_installed_robot(work, prefix)
    except Failure as e:
        print(f"FAILED: {e}", file=sys.stderr, flush=True)
        return 1
    print("-- package test passed", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
