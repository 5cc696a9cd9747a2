#!/usr/bin/env python3
"""Checks keel's documentation: README.md and docs/**/*.md.

For every markdown link or image that is not http(s) or mailto:
  - the target exists, relative to the linking file, and stays inside the repository;
  - a #fragment names a heading of the target markdown file (GitHub's slug: lower case,
    punctuation removed except hyphens, underscores and spaces, each space a hyphen; a repeated
    heading gets -1, -2, ...), or an explicit <a name="..."> / id="..." anchor.
Links inside code (fenced blocks, `spans`) are not links and are not checked.

Also fails on any reference to the design folder outside the repository (../shared/, SPEC,
ARCHITECTURE.md, ROBOT.md, STYLE.md), on a path of one machine (/work/..., /home/...) and on a
project issue number ("issue 14": the tree's readers have no tracker to look it up in; a public
project's issue beside its https:// address is a reference like any other). These rules hold for
the docs and for every source file of the tree too (src, include, tests, bench, robot, examples,
fuzz, msgs, scripts, .ci, the CMake files, package.xml): keel's comments stand alone. And a clang-tidy
suppression in C++ names its checks and says why, `// NOLINT(check-name): the reason`, so that
a reader can judge it and it hides nothing else.

Prints `file:line: broken link X (why)` per problem and exits 1, or prints one summary line and
exits 0. Standard library only. Usage: python3 scripts/check_docs.py [REPO_ROOT]
"""

import os
import re
import sys
import unicodedata
from urllib.parse import unquote

# Text that points at the design folder outside the repository. Case-sensitive: "SPEC" is the
# name of that document, not a word of ordinary prose.
FORBIDDEN = [
    (re.compile(r"\.\./shared\b|/work/shared\b|\bshared/design\b"), "the design folder outside the repository"),
    (re.compile(r"\bSPEC\b(\.md)?"), "SPEC.md is outside the repository"),
    (re.compile(r"\bARCHITECTURE\.md\b"), "ARCHITECTURE.md is outside the repository"),
    (re.compile(r"\bROBOT\.md\b"), "ROBOT.md is outside the repository"),
    (re.compile(r"\bSTYLE\.md\b"), "STYLE.md is outside the repository"),
]

# The same rules' further two, for docs and sources alike.
MACHINE_PATH = (re.compile(r"(?<![\w.~-])/(?:work|home|check)/[\w.-]+"), "a path of one machine")
ISSUE = (re.compile(r"\b[Ii]ssues?[ -]#?\d+"), "an issue number: say what the work is")
SOURCE_DIRS = ["src", "include", "tests", "bench", "robot", "examples", "fuzz", "msgs", "scripts", ".ci"]
SOURCE_SKIP = {"node_modules", "venv", "__pycache__"}
SOURCE_SUFFIXES = (".cpp", ".hpp", ".h", ".c", ".py", ".sh", ".mjs", ".js", ".cmake", ".xml", ".json", ".html",
                   ".css", ".txt", ".idl", ".msg", ".yaml", ".yml")


def source_files(root):
    """Every source file of the tree the rules above hold for (the checker itself excepted: it
    names what it looks for)."""
    out = []
    for top in SOURCE_DIRS:
        for d, dirs, names in os.walk(os.path.join(root, top)):
            dirs[:] = [x for x in dirs if x not in SOURCE_SKIP]
            for name in names:
                path = os.path.join(d, name)
                if (name.endswith(SOURCE_SUFFIXES) or name in ("run", "stage")) and \
                        os.path.abspath(path) != os.path.abspath(__file__):
                    out.append(path)
    for name in os.listdir(root):
        if name in ("CMakeLists.txt", "package.xml") or name.endswith(".json"):
            out.append(os.path.join(root, name))
    return sorted(out)


NOLINT = re.compile(r"NOLINT(?:NEXTLINE|BEGIN|END)?\b(\([^)]*\))?(:\s*\S.*)?")
CXX_SUFFIXES = (".cpp", ".hpp", ".h", ".c")


def line_problems(line, cxx=False):
    """(matched text, why) for each rule a line of a doc or source breaks."""
    for pattern, why in FORBIDDEN + [MACHINE_PATH]:
        m = pattern.search(line)
        if m:
            yield m.group(0), why
    m = ISSUE[0].search(line)
    if m and not re.search(r"https?://", line):
        yield m.group(0), ISSUE[1]
    if cxx:
        for m in NOLINT.finditer(line):
            if not m.group(1):
                yield m.group(0).strip(), "a NOLINT names the checks it suppresses: NOLINT(check-name): why"
            elif not m.group(0).startswith("NOLINTEND") and not m.group(2):
                yield m.group(0).strip(), "a NOLINT says why: NOLINT(check-name): the reason"


FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
HEADING = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)[ \t]*#*[ \t]*$")
SETEXT = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
INLINE_LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\(\s*(<[^>]*>|[^\s()]*(?:\([^\s()]*\)[^\s()]*)*)(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
REF_LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\[([^\]]*)\]")
REF_DEF = re.compile(r"^ {0,3}\[([^\]]+)\]:\s*(<[^>]*>|\S+)")
HTML_ANCHOR = re.compile(r"""<a\s[^>]*\b(?:name|id)\s*=\s*["']([^"']+)["']""", re.I)
CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def slug(text):
    """GitHub's heading anchor for the heading's rendered text."""
    out = []
    for ch in text.lower():
        cat = unicodedata.category(ch)
        if ch in " -" or cat[0] in "LMN" or cat == "Pc":
            out.append("-" if ch == " " else ch)
    return "".join(out)


def heading_text(raw):
    """The text GitHub renders for a heading's markdown (what the slug is made from)."""
    parts = []
    pos = 0
    for m in CODE_SPAN.finditer(raw):  # code keeps its characters, underscores included
        parts.append(("md", raw[pos:m.start()]))
        parts.append(("code", m.group(2).strip()))
        pos = m.end()
    parts.append(("md", raw[pos:]))
    text = ""
    for kind, s in parts:
        if kind == "md":
            s = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", s)  # links and images: their text
            s = re.sub(r"<[^>]+>", "", s)                     # inline HTML
            s = re.sub(r"(?<!\w)[*_]+|[*_]+(?!\w)", "", s)     # emphasis markers
        text += s
    return text.strip()


class Doc:
    """A markdown file: its lines outside code, its anchors."""

    def __init__(self, path):
        self.path = path
        with open(path, encoding="utf-8") as f:
            self.lines = f.read().split("\n")
        self.prose = []  # (line number, text with code removed)
        self.refs = {}   # reference definitions: label -> target
        self.anchors = set()
        counts = {}
        fence = None
        prev = None  # the previous prose line, for setext headings
        for n, line in enumerate(self.lines, 1):
            m = FENCE.match(line)
            if fence:
                if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                    fence = None
                prev = None
                continue
            if m:
                fence = m.group(1)
                prev = None
                continue
            title = None
            h = HEADING.match(line)
            if h:
                title = h.group(2)
            elif prev and prev.strip() and SETEXT.match(line) and not HEADING.match(prev):
                title = prev.strip()
            if title is not None:
                base = slug(heading_text(title))
                k = counts.get(base, 0)
                counts[base] = k + 1
                self.anchors.add(base if k == 0 else f"{base}-{k}")
            for a in HTML_ANCHOR.finditer(line):
                self.anchors.add(a.group(1))
            d = REF_DEF.match(line)
            if d:
                self.refs[d.group(1).strip().lower()] = (n, d.group(2))
            self.prose.append((n, CODE_SPAN.sub(lambda c: " " * len(c.group(0)), line)))
            prev = line

    def links(self):
        """(line, target) for every inline, reference and definition link outside code."""
        for n, text in self.prose:
            if REF_DEF.match(text):
                continue
            for m in INLINE_LINK.finditer(text):
                yield n, m.group(2)
            for m in REF_LINK.finditer(text):
                label = (m.group(2) or m.group(1)).strip().lower()
                if label in self.refs:
                    yield n, self.refs[label][1]
        for label, (n, target) in self.refs.items():
            yield n, target


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    files = [os.path.join(root, "README.md")]
    for d, _, names in os.walk(os.path.join(root, "docs")):
        files += [os.path.join(d, f) for f in names if f.endswith(".md")]
    files.sort()
    docs = {}

    def doc(path):
        if path not in docs:
            docs[path] = Doc(path)
        return docs[path]

    problems = []
    warnings = []
    n_links = 0
    for path in files:
        rel = os.path.relpath(path, root)
        d = doc(path)
        for n, line in enumerate(d.lines, 1):
            for text, why in line_problems(line):
                problems.append(f"{rel}:{n}: {text} ({why})")
        for n, target in d.links():
            n_links += 1
            t = target[1:-1] if target.startswith("<") and target.endswith(">") else target
            if re.match(r"^[a-z][a-z0-9+.-]*:", t, re.I):
                if not re.match(r"^(https?|mailto):", t, re.I):
                    problems.append(f"{rel}:{n}: broken link {target} (unsupported scheme)")
                continue
            file_part, _, fragment = t.partition("#")
            file_part = unquote(file_part)
            if file_part.startswith("/"):
                problems.append(f"{rel}:{n}: broken link {target} (absolute path: links are relative)")
                continue
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            if os.path.relpath(dest, root).startswith(".."):
                problems.append(f"{rel}:{n}: broken link {target} (outside the repository)")
                continue
            if not os.path.exists(dest):
                problems.append(f"{rel}:{n}: broken link {target} (no such file: {os.path.relpath(dest, root)})")
                continue
            if not fragment:
                continue
            fragment = unquote(fragment)
            dest_rel = os.path.relpath(dest, root)
            if dest.endswith(".md") and os.path.isfile(dest):
                if fragment not in doc(dest).anchors:
                    problems.append(f"{rel}:{n}: broken link {target} "
                                    f"(no heading '#{fragment}' in {os.path.relpath(dest, root)})")
            elif not re.fullmatch(r"L\d+(-L\d+)?", fragment):
                problems.append(f"{rel}:{n}: broken link {target} (a fragment on a file that is not markdown)")

    sources = source_files(root)
    for path in sources:
        rel = os.path.relpath(path, root)
        try:
            with open(path, encoding="utf-8") as f:
                lines = f.read().split("\n")
        except UnicodeDecodeError:
            continue  # not text
        cxx = path.endswith(CXX_SUFFIXES)
        for n, line in enumerate(lines, 1):
            for text, why in line_problems(line, cxx):
                problems.append(f"{rel}:{n}: {text} ({why})")

    for w in warnings:
        print(w, file=sys.stderr)
    if problems:
        def where(p):
            f, line = p.split(":")[:2]
            return (f, int(line))
        problems.sort(key=where)
        for p in problems:
            print(p)
        print(f"check_docs: {len(problems)} problem(s) in {len(files)} files", file=sys.stderr)
        return 1
    print(f"check_docs: {len(files)} files, {n_links} links, every target and anchor resolves; "
          f"no reference outside the repository, in them or in {len(sources)} source files")
    return 0


if __name__ == "__main__":
    sys.exit(main())
