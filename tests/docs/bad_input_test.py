#!/usr/bin/env python3
"""docs/bad-input.md names, for each kind of bad input, the tests that hold keel to it: each
name `Suite.Test` (a `*` stands for any characters) must be a TEST, TEST_F or TEST_P of the
suite, or a CTest test of that name (`add_test(NAME Suite.Test` in a tests/ CMakeLists.txt: the
tests with independent peers, tests/monitor), so that the table cannot point at a test that was
renamed or removed.
Usage: bad_input_test.py (from anywhere; exit 1 naming each missing test)."""
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    with open(os.path.join(ROOT, "docs", "bad-input.md"), encoding="utf-8") as f:
        doc = f.read()
    names = sorted(set(re.findall(r"`([A-Z][A-Za-z]+)\.([A-Za-z*]+)`", doc)))
    sources = ""
    for pattern in ("*.cpp", "CMakeLists.txt"):
        for path in glob.glob(os.path.join(ROOT, "tests", "**", pattern), recursive=True):
            with open(path, encoding="utf-8") as f:
                sources += f.read()
    missing = []
    for suite, test in names:
        name = test.replace("*", r"\w*")
        pattern = r"TEST(_F|_P)?\(\s*(\w+/)?%s,\s*%s\)" % (suite, name)
        ctest = r"add_test\(NAME %s\.%s\b" % (suite, name)
        if not re.search(pattern, sources) and not re.search(ctest, sources):
            missing.append("%s.%s" % (suite, test))
    for m in missing:
        print("docs/bad-input.md names %s, which no test defines" % m)
    if not names:
        print("docs/bad-input.md names no test")
        return 1
    print("%d test names in docs/bad-input.md, %d missing" % (len(names), len(missing)))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
