#!/usr/bin/env python3
"""Every XML and shell example in README.md, the tutorial and docs/ runs as written.

Each fenced block of kind xml, sh, bash or console says, in an HTML comment on the line before
it, how it is checked:

  <!-- example: validate [as PATH] [in DIR] [beside FILE...] -->
      a whole document (a profile, a fault scenario): `keel validate`, saved as PATH (so that
      later examples can reference it) or as a file of its own in DIR; FILEs are copied next to
      it first. Paths are the repository's.
  <!-- example: fragment of FILE replacing XPATH -->
  <!-- example: fragment of FILE into XPATH -->
      a piece of a profile: put in a copy of FILE in place of, or inside, the element XPATH
      finds (ElementTree's syntax), and the copy validated.
  <!-- example: run -->
      shell commands, run from the repository's root with bash -e (console blocks: the lines
      after `$ `); `keel` and `build/bin/keel` are the keel under test. They must succeed.
  <!-- example: not run: REASON -->
      shown, not checked, and why (a run of minutes, root, a network).

A block without such a comment fails the test: a new example says how it is checked. Files the
examples write go to a scratch directory; the repository is only read.

  examples_test.py KEEL_BINARY"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

ROOT = pathlib.Path(__file__).resolve().parents[2]
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```", re.S | re.M)
NOTE = re.compile(r"<!--\s*example:\s*(.*?)\s*-->\s*$")
CHECKED = {"xml", "sh", "bash", "console"}


def documents():
    yield ROOT / "README.md"
    yield ROOT / "examples" / "README.md"  # the tutorial
    yield from sorted((ROOT / "docs").rglob("*.md"))


def examples():
    """(file, line, kind, body, note) for every checked block."""
    for doc in documents():
        text = doc.read_text()
        for m in FENCE.finditer(text):
            if m.group(1) not in CHECKED:
                continue
            line = text.count("\n", 0, m.start()) + 1
            before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
            note = NOTE.search(before)
            yield doc.relative_to(ROOT), line, m.group(1), m.group(2), note.group(1) if note else None


class Workspace:
    """A scratch copy of the repository's XML, where examples are written and validated, and a
    directory the shell examples run in (the repository's top level linked in)."""

    def __init__(self, keel: pathlib.Path, tmp: pathlib.Path):
        self.keel = keel
        self.xml = tmp / "xml"
        for f in ROOT.rglob("*.xml"):
            rel = f.relative_to(ROOT)
            if rel.parts[0].startswith(("build", ".")):
                continue
            (self.xml / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(f, self.xml / rel)
        self.run_dir = tmp / "run"
        self.run_dir.mkdir()
        for entry in ROOT.iterdir():
            if not entry.name.startswith((".", "build")):
                (self.run_dir / entry.name).symlink_to(entry)
        # build/bin/keel is the keel under test; only its bin/ and lib/ are linked, so nothing an
        # example runs can configure or build in the real build directory.
        (self.run_dir / "build").mkdir()
        for part in ("bin", "lib"):
            (self.run_dir / "build" / part).symlink_to(keel.parent.parent / part)
        self.count = 0

    def validate(self, path: pathlib.Path):
        r = subprocess.run([str(self.keel), "validate", str(path)], capture_output=True, text=True, timeout=60)
        return None if r.returncode == 0 else (r.stderr or r.stdout).replace(str(self.xml) + "/", "")

    def scratch(self, directory: str) -> pathlib.Path:
        self.count += 1
        return self.xml / directory / f"_example_{self.count}.xml"

    def check_document(self, body: str, args: str):
        m = re.fullmatch(r"validate(?: as (\S+))?(?: in (\S+))?(?: beside (.+))?", args)
        if not m:
            return f"cannot read the note 'example: {args}'"
        path = self.xml / m.group(1) if m.group(1) else self.scratch(m.group(2) or ".")
        path.parent.mkdir(parents=True, exist_ok=True)
        for f in (m.group(3) or "").split():
            shutil.copyfile(ROOT / f, path.parent / pathlib.Path(f).name)
        path.write_text(body)
        return self.validate(path)

    def check_fragment(self, body: str, args: str):
        m = re.fullmatch(r"fragment of (\S+) (replacing|into) (.+)", args)
        if not m:
            return f"cannot read the note 'example: {args}'"
        target, how, where = self.xml / m.group(1), m.group(2), m.group(3)
        try:
            tree = ET.parse(target)
            pieces = list(ET.fromstring(f"<fragment>{body}</fragment>"))
        except ET.ParseError as e:
            return f"not well-formed XML ({m.group(1)} or the example): {e}"
        root = tree.getroot()
        parents = {child: parent for parent in root.iter() for child in parent}
        found = root.find(where) if where not in (".", "/") else root
        if found is None:
            return f"{m.group(1)} has no element at {where}"
        if how == "into":
            found.extend(pieces)
        else:
            parent = parents[found]
            at = list(parent).index(found)
            parent.remove(found)
            for i, piece in enumerate(pieces):
                parent.insert(at + i, piece)
        path = self.scratch(str(pathlib.Path(m.group(1)).parent))
        tree.write(path, encoding="unicode")
        return self.validate(path)

    def run(self, kind: str, body: str):
        if kind == "console":
            body = "\n".join(l[2:] for l in body.splitlines() if l.startswith("$ "))
        env = dict(os.environ, PATH=f"{self.keel.parent}:{os.environ['PATH']}")
        r = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", body], cwd=self.run_dir, env=env,
                           capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            return f"exit {r.returncode}:\n{r.stderr[-2000:] or r.stdout[-2000:]}"
        return None


def main() -> int:
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    keel = pathlib.Path(sys.argv[1]).resolve()
    failures, checked, shown = [], 0, []
    with tempfile.TemporaryDirectory(prefix="keel_examples_") as tmp:
        ws = Workspace(keel, pathlib.Path(tmp))
        for doc, line, kind, body, note in examples():
            where = f"{doc}:{line}"
            if note is None:
                failures.append(f"{where}: a {kind} example without a note saying how it is checked "
                                "(<!-- example: ... --> on the line before it; see tests/docs/examples_test.py)")
                continue
            if note.startswith("not run:"):
                shown.append(f"{where}: {note}")
                continue
            if kind == "xml" and note.startswith("validate"):
                problem = ws.check_document(body, note)
            elif kind == "xml" and note.startswith("fragment"):
                problem = ws.check_fragment(body, note)
            elif kind != "xml" and note == "run":
                problem = ws.run(kind, body)
            else:
                problem = f"a {kind} example cannot be checked by 'example: {note}'"
            checked += 1
            if problem:
                failures.append(f"{where}: {problem.strip()}")
    for f in failures:
        print("FAIL", f)
    for s in shown:
        print("shown, not run:", s)
    print(f"examples_test: {checked} examples checked, {len(shown)} shown only, {len(failures)} failing")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
