#!/usr/bin/env python3
"""scripts/lib/tidy_cache.py, the cache of clang-tidy's results scripts/tidy.sh keeps: a result
is reused only when everything it depends on is the same, and found again from a clone at
another path.

Runs the real clang-tidy and clang (Debian's clang-tidy and clang-14; exit 77, skipped, when
either is missing) on a two-file project in a temporary directory."""
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CACHE_PY = ROOT / "scripts" / "lib" / "tidy_cache.py"
TIDY = shutil.which("clang-tidy")
CLANG = shutil.which("clang++-14")
FLAGS = "--quiet --use-color=false"


def make_project(top: pathlib.Path):
    (top / "src").mkdir(parents=True)
    (top / "build").mkdir()
    (top / "src" / "a.hpp").write_text("#pragma once\ninline int twice(int x) { return 2 * x; }\n")
    (top / "src" / "a.cpp").write_text('#include "a.hpp"\nint f() { return twice(3); }\n')
    (top / ".clang-tidy").write_text("Checks: '-*,readability-braces-around-statements'\n")
    db = [{"directory": str(top / "build"), "file": str(top / "src" / "a.cpp"),
           "command": f"/usr/bin/c++ -I{top}/src -O2 -o a.o -c {top}/src/a.cpp"}]
    (top / "build" / "compile_commands.json").write_text(json.dumps(db))


class TidyCache(unittest.TestCase):
    def setUp(self):
        self.tmp = pathlib.Path(tempfile.mkdtemp())
        self.cache = self.tmp / "cache"
        self.addCleanup(shutil.rmtree, self.tmp)

    def lookup(self, top):
        """The files tidy_cache.py leaves for clang-tidy to run on, and the number of hits."""
        out = pathlib.Path(tempfile.mkdtemp(dir=self.tmp))
        r = subprocess.run([sys.executable, CACHE_PY, "lookup", top / "build" / "compile_commands.json", top,
                            top / "build", self.cache, out, TIDY, FLAGS, str(top / "src" / "a.cpp")],
                           capture_output=True, check=True)
        todo = [p for p in r.stdout.decode().split("\0") if p]
        hits = int((out / "hits").read_text().split()[0])
        return out, todo, hits

    def tidy_and_store(self, top, out, todo):
        for path in todo:
            name = path.replace("/", "_")
            r = subprocess.run([TIDY, "-p", top / "build", *FLAGS.split(), path], capture_output=True, text=True)
            (out / f"{name}.out").write_text(r.stdout)
            if r.returncode != 0:  # a finding (WarningsAsErrors), as tidy.sh marks it
                (out / f"{name}.found").write_text(path)
        subprocess.run([sys.executable, CACHE_PY, "store", top, top / "build", self.cache, out], check=True)

    def test_a_result_is_reused_at_another_path_and_not_once_anything_it_depends_on_changed(self):
        first = self.tmp / "one" / "keel"
        make_project(first)
        out, todo, hits = self.lookup(first)
        self.assertEqual((todo, hits), ([str(first / "src" / "a.cpp")], 0))
        self.tidy_and_store(first, out, todo)
        self.assertEqual(self.lookup(first)[1:], ([], 1), "the same file again is a hit")

        # A clone at another path (a deeper one: no path of the first is in the key).
        second = self.tmp / "two" / "deeper" / "keel"
        shutil.copytree(first, second)
        (second / "build" / "compile_commands.json").write_text(
            (first / "build" / "compile_commands.json").read_text().replace(str(first), str(second)))
        out, todo, hits = self.lookup(second)
        self.assertEqual((todo, hits), ([], 1), "a clone at another path hits")
        name = str(second / "src" / "a.cpp").replace("/", "_")
        self.assertNotIn(str(first), (out / f"{name}.out").read_text(), "the hit names the clone's own paths")

        # Each thing the result depends on, changed alone, is a miss.
        changes = {
            "a header it includes": ("src/a.hpp", lambda t: t.replace("2 * x", "x + x")),
            "a comment (a NOLINT could be one)": ("src/a.hpp", lambda t: t + "// NOLINT\n"),
            "the configuration": (".clang-tidy", lambda t: t.replace("'\n", ",misc-unused-parameters'\n")),
            "a configuration nearer the file": ("src/.clang-tidy", lambda t: "InheritParentConfig: true\n"),
            "the compile command": ("build/compile_commands.json", lambda t: t.replace("-O2", "-O2 -DX=1")),
        }
        for i, (what, (rel, change)) in enumerate(changes.items()):
            with self.subTest(what):
                third = self.tmp / f"changed{i}" / "keel"
                shutil.copytree(second, third)
                db = third / "build" / "compile_commands.json"
                db.write_text(db.read_text().replace(str(second), str(third)))
                path = third / rel
                path.write_text(change(path.read_text() if path.exists() else ""))
                self.assertEqual(self.lookup(third)[1:], ([str(third / "src" / "a.cpp")], 0))

    def test_a_failed_run_is_not_kept(self):
        top = self.tmp / "keel"
        make_project(top)
        (top / "src" / "a.cpp").write_text('#include "a.hpp"\nint f(int x) { if (x) return twice(3); return 0; }\n')
        (top / ".clang-tidy").write_text("Checks: '-*,readability-braces-around-statements'\nWarningsAsErrors: '*'\n")
        out, todo, _ = self.lookup(top)
        self.tidy_and_store(top, out, todo)
        self.assertEqual(self.lookup(top)[1:], ([str(top / "src" / "a.cpp")], 0), "a finding is never a hit")


if __name__ == "__main__":
    if not TIDY or not CLANG:
        print("tidy_cache_test: needs clang-tidy and clang++-14 (.ci/stage deps installs them); skipped")
        sys.exit(77)
    unittest.main()
