#!/usr/bin/env python3
"""clang-tidy's results, reused from a cache keyed by everything a result depends on
(scripts/tidy.sh; docs/decisions/0020-ci-time.md).

  tidy_cache.py lookup DB ROOT BUILD CACHE OUT TIDY FLAGS FILE...
      For each FILE (a translation unit of DB): its key is the hash of clang-tidy's version, the
      configuration (ROOT/.clang-tidy, and any .clang-tidy between ROOT and the file), the
      flags tidy.sh passes it (FLAGS, one string), the file's compile command, and its
      preprocessed source with comments kept (`clang -E -C`: every header it includes, every
      NOLINT); paths under BUILD and ROOT are written as
      placeholders, so that a clone at another path has the same keys. A key found in CACHE
      writes the file's clang-tidy output to OUT as a run would have; the other files are
      printed, NUL-separated, for tidy.sh to run clang-tidy on, with their keys left in OUT.
  tidy_cache.py store ROOT BUILD CACHE OUT
      Keeps the output of each file that clang-tidy passed (no finding, no failure) under its key.

Preprocessing runs on as many cores as there are ($KEEL_JOBS to choose). A file that cannot be
preprocessed is simply not looked up: clang-tidy runs on it and says what is wrong."""
import concurrent.futures
import hashlib
import json
import os
import shlex
import subprocess
import sys


def out_name(path):
    return path.replace("/", "_")


def placeholders(text, root, build):
    return text.replace(build, "@BUILD@").replace(root, "@ROOT@")


def command_of(entry):
    if "arguments" in entry:
        return list(entry["arguments"])
    return shlex.split(entry["command"])


def preprocess_args(args, clang):
    """The compile command turned into clang's preprocessor: no output file, -E -C."""
    out, skip = [clang], False
    for a in args[1:]:
        if skip:
            skip = False
            continue
        if a in ("-o", "-MF", "-MT", "-MQ"):
            skip = True
            continue
        if a in ("-c", "-MD", "-MMD") or a.startswith("-o"):
            continue
        out.append(a)
    return out + ["-E", "-C", "-Wno-unknown-warning-option", "-o", "-"]


def lookup(db, root, build, cache, out, tidy, flags, files):
    entries = {}
    for e in json.load(open(db)):
        path = os.path.realpath(os.path.join(e.get("directory", ""), e["file"]))
        entries.setdefault(path, e)
    version = subprocess.run([tidy, "--version"], capture_output=True, text=True, check=True).stdout
    config = open(os.path.join(root, ".clang-tidy"), "rb").read()

    def nested_configs(path):
        """The .clang-tidy files between ROOT and the file's directory (tests/.clang-tidy)."""
        parts, d = [], os.path.dirname(path)
        while d.startswith(root + os.sep):
            c = os.path.join(d, ".clang-tidy")
            if os.path.exists(c):
                parts.append(placeholders(c, root, build).encode() + b"\0" + open(c, "rb").read())
            d = os.path.dirname(d)
        return parts
    clang = os.environ.get("KEEL_TIDY_CLANG", "clang++-14")
    common = hashlib.sha256()
    for part in (version.encode(), config, flags.encode()):
        common.update(len(part).to_bytes(8, "little") + part)

    def key_of(path):
        e = entries.get(path)
        if e is None:
            return None
        args = command_of(e)
        try:
            pre = subprocess.run(preprocess_args(args, clang), cwd=e.get("directory", "."),
                                 capture_output=True, check=True).stdout
        except (OSError, subprocess.CalledProcessError):
            return None
        h = common.copy()
        for part in (*nested_configs(path), placeholders(" ".join(args[1:]), root, build).encode(),
                     placeholders(path, root, build).encode(),
                     placeholders(pre.decode("utf-8", "replace"), root, build).encode()):
            h.update(len(part).to_bytes(8, "little") + part)
        return h.hexdigest()

    jobs = int(os.environ.get("KEEL_JOBS") or os.cpu_count() or 2)
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        keys = list(pool.map(key_of, files))
    hits = 0
    for path, key in zip(files, keys):
        name = out_name(path)
        hit = key and os.path.join(cache, key[:2], key)
        if hit and os.path.exists(hit + ".out"):
            text = open(hit + ".out", encoding="utf-8", errors="replace").read()
            open(os.path.join(out, name + ".out"), "w").write(
                text.replace("@BUILD@", build).replace("@ROOT@", root))
            os.utime(hit + ".out")  # recently used: what a size bound would keep
            hits += 1
            continue
        if key:
            open(os.path.join(out, name + ".key"), "w").write(key)
        sys.stdout.write(path + "\0")
    open(os.path.join(out, "hits"), "w").write(f"{hits} {len(files)}\n")


def store(root, build, cache, out):
    for entry in os.listdir(out):
        if not entry.endswith(".key"):
            continue
        name = entry[:-4]
        if any(os.path.exists(os.path.join(out, name + end)) for end in (".failed", ".found")):
            continue  # not checked, or with findings: run again next time
        key = open(os.path.join(out, entry)).read().strip()
        text = open(os.path.join(out, name + ".out"), encoding="utf-8", errors="replace").read()
        os.makedirs(os.path.join(cache, key[:2]), exist_ok=True)
        tmp = os.path.join(cache, key[:2], f".{key}.{os.getpid()}")
        open(tmp, "w").write(placeholders(text, root, build))
        os.replace(tmp, os.path.join(cache, key[:2], key + ".out"))  # whole or not at all


def main(argv):
    if len(argv) >= 9 and argv[1] == "lookup":
        db, root, build, cache, out, tidy, flags = argv[2:9]
        lookup(db, root, build, cache, out, tidy, flags, argv[9:])
    elif len(argv) == 6 and argv[1] == "store":
        store(*argv[2:6])
    else:
        sys.stderr.write(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
