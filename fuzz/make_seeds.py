#!/usr/bin/env python3
"""Regenerates the fuzz targets' XML seeds and dictionary from the repository (docs/fuzzing.md).

fuzz/corpus/<target>/ gets a relative link to every profile and fault scenario of the
repository whose root element is the target's kind; fuzz/xml.dict gets every element and
attribute name found in them and their short values. Run from anywhere:
    python3 fuzz/make_seeds.py
The motion board's seeds (binary frames) are not generated here: they are checked in.
"""
import glob
import os
import re
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KINDS = {
    "component_profile": "profile_component",
    "composite_component_profile": "profile_composite",
    "package_profile": "profile_package",
    "application_profile": "profile_package",
    "system_profile": "profile_system",
    "fault_scenario": "scenario",
}


def main():
    os.chdir(ROOT)
    elements, attributes, values = set(), set(), set()
    by_target = {}
    for base in ["tests", "robot", "examples", "components", "bench"]:
        for path in sorted(glob.glob(base + "/**/*.xml", recursive=True)):
            try:
                root = ET.parse(path).getroot()
            except ET.ParseError:
                continue  # a deliberately malformed test input: not a seed of its kind
            except ValueError:  # an encoding Python's parser lacks (OPRoS's euc-kr): a seed still
                tag = re.search(rb"<([A-Za-z_][\w.-]*)", re.sub(rb"<[?!][^>]*>", b"", open(path, "rb").read()))
                if tag and KINDS.get(tag.group(1).decode()):
                    by_target.setdefault(KINDS[tag.group(1).decode()], []).append(path)
                continue
            target = KINDS.get(root.tag)
            if target:
                by_target.setdefault(target, []).append(path)
            for el in root.iter():
                if not isinstance(el.tag, str):
                    continue
                elements.add(el.tag)
                for name, value in el.attrib.items():
                    attributes.add(name)
                    if len(value) < 24:
                        values.add(value)
                text = (el.text or "").strip()
                if text and len(text) < 24 and " " not in text:
                    values.add(text)
    for target, paths in by_target.items():
        folder = os.path.join("fuzz", "corpus", target)
        os.makedirs(folder, exist_ok=True)
        for path in paths:
            link = os.path.join(folder, path.replace("/", "_"))
            if not os.path.lexists(link):
                os.symlink(os.path.relpath(path, folder), link)
    with open("fuzz/xml.dict", "w") as out:
        out.write("# libFuzzer dictionary for keel's XML inputs (profiles and fault scenarios): every element and\n"
                  "# attribute name found in the repository's profiles, and their short values. Made by\n"
                  "# fuzz/make_seeds.py.\n")
        for token in ['<?xml version="1.0" encoding="UTF-8"?>', "<!--", "-->", "<![CDATA[", "]]>", "/>"]:
            out.write('"%s"\n' % token.replace('"', '\\"'))
        for name in sorted(elements):
            out.write('"<%s>"\n"</%s>"\n' % (name, name))
        for name in sorted(attributes):
            out.write('"%s=\\""\n' % name)
        for value in sorted(values):
            escaped = value.replace("\\", "\\\\").replace('"', '\\"')
            if all(32 <= ord(c) < 127 for c in escaped):
                out.write('"%s"\n' % escaped)
    for target in sorted(by_target):
        print("%s: %d seeds" % (target, len(by_target[target])))


if __name__ == "__main__":
    main()
