#!/usr/bin/env python3
"""keel's package.xml says what its CMake build does, so that a ROS 2 workspace builds it.

1. package.xml is a format 3 manifest of a package named keel, of build type cmake, with cmake
   as its build tool.
2. Its version is the CMake project's (PROJECT_VERSION, from project() in CMakeLists.txt): the
   one place the version is written, and the one `keel --version` prints.
3. Every package keel's CMake files look for (find_package, find_dependency, find_program) has
   its rosdep key among package.xml's dependencies, by the table below; a new one without a key
   here fails until it is added to both.

Reads the files only (Python's standard library, no ROS tool): it runs wherever the suite does.
Exits non-zero, naming the check that failed.
Called by CTest (tests/package/CMakeLists.txt); by hand:
  manifest_test.py --source <keel checkout> --version <x.y.z>
"""
import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

# What CMake looks for -> its rosdep key (rosdistro's rosdep/base.yaml and python.yaml), or None
# and why none is needed.
KEYS = {
    "pugixml": "pugixml-dev",
    "fmt": "fmt",
    "nlohmann_json": "nlohmann-json-dev",
    "Boost": "libboost-dev",  # the headers alone (Beast, Asio); `boost` would be all of Boost
    "Eigen3": "eigen",  # the state estimator's linear algebra, header-only
    "CLI11": "cli11",
    "CycloneDDS": "cyclonedds",
    "idlc": "cyclonedds",  # CycloneDDS's IDL compiler, part of ROS 2's cyclonedds package
    "Python3": "python3",
    "GTest": "gtest",
    "benchmark": "benchmark",
    "node": "nodejs",
    "Threads": None,  # the C library's
    "keel": None,  # keel itself, in the examples and in the projects the package tests build
    "ccache": None,  # no rosdep key; the presets' compiler launcher (scripts/deps.sh installs it)
}
DEPENDS = ("depend", "build_depend", "build_export_depend", "exec_depend", "test_depend",
           "buildtool_depend")
FIND = re.compile(r"\bfind_(?:package|dependency)\(\s*(\w+)|\bfind_program\(\s*\w+\s+(\w+)")
SKIP = {".git", "third_party", "node_modules", "venv", "__pycache__"}


class Failure(Exception):
    pass


def expect(condition, message):
    if not condition:
        raise Failure(message)


def read_manifest(path):
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        raise Failure(f"{path}: cannot be read as XML: {e}")
    expect(root.tag == "package" and root.get("format") == "3",
           f"{path}: the root is <{root.tag} format={root.get('format')!r}>, want <package format=\"3\">")
    return root


def text(root, path):
    element = root.find(path)
    return element.text.strip() if element is not None and element.text else ""


def cmake_files(source):
    """keel's CMake files: every CMakeLists.txt and *.cmake(.in), build trees left out."""
    for directory, subdirs, files in os.walk(source):
        subdirs[:] = sorted(d for d in subdirs if d not in SKIP and not d.startswith("build"))
        for name in sorted(files):
            if name == "CMakeLists.txt" or name.endswith((".cmake", ".cmake.in")):
                yield Path(directory) / name


def looked_for(source):
    """{name CMake looks for: first file:line that does}, comments left out."""
    found = {}
    for path in cmake_files(source):
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            for m in FIND.finditer(line.split("#", 1)[0]):
                found.setdefault(m.group(1) or m.group(2), f"{path.relative_to(source)}:{number}")
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True, type=Path, help="keel's source tree")
    parser.add_argument("--version", required=True, help="the CMake project's version")
    args = parser.parse_args()
    manifest = args.source / "package.xml"
    try:
        root = read_manifest(manifest)
        expect(text(root, "name") == "keel", f"{manifest}: <name> is {text(root, 'name')!r}, want 'keel'")
        version = text(root, "version")
        expect(version == args.version,
               f"{manifest}: <version> is {version!r}, CMakeLists.txt's project() says {args.version!r}: "
               "change both together")
        expect(text(root, "export/build_type") == "cmake",
               f"{manifest}: <export><build_type> is {text(root, 'export/build_type')!r}, want 'cmake'")
        tools = [e.text.strip() for e in root.findall("buildtool_depend") if e.text]
        expect("cmake" in tools, f"{manifest}: no <buildtool_depend>cmake</buildtool_depend>")
        keys = {e.text.strip() for tag in DEPENDS for e in root.findall(tag) if e.text}
        for name, where in sorted(looked_for(args.source).items()):
            expect(name in KEYS, f"{where}: CMake looks for '{name}', which {Path(__file__).name} does not "
                   "know: add its rosdep key to package.xml and to the table KEYS")
            expect(KEYS[name] is None or KEYS[name] in keys,
                   f"{where}: CMake looks for '{name}', and {manifest} does not depend on its rosdep key "
                   f"'{KEYS[name]}'")
        print(f"-- package.xml: keel {version}, build type cmake, {len(keys)} dependencies, one for each "
              "package CMake looks for", flush=True)
    except Failure as e:
        print(f"FAILED: {e}", file=sys.stderr, flush=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
