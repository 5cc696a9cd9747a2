#!/usr/bin/env python3
"""Regenerates the fuzz targets' XML seeds and dictionary from the repository (docs/fuzzing.md).

fuzz/corpus/<target>/ gets a relative link to every profile and fault scenario of the
repository whose root element is the target's kind; fuzz/xml.dict gets every element and
attribute name found in them and their short values. fuzz/corpus/monitor_client/ gets the
Foxglove client messages below (their first byte picks the frame's kind: '0' text, '1' binary),
and fuzz/monitor_client.dict the protocol's JSON vocabulary. Run from anywhere:
    python3 fuzz/make_seeds.py
The motion board's seeds (binary frames) are not generated here: they are checked in. The MCAP
reader's are written by keel's own writer: build-asan/fuzz/mcap_seeds (docs/fuzzing.md).
"""
import glob
import os
import re
import struct
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KINDS = {
    "component_profile": "profile_component",
    "composite_component_profile": "profile_composite",
    "package_profile": "profile_package",
    "application_profile": "profile_package",
    "system_profile": "profile_system",
    "service_port_type_profile": "profile_types",
    "data_type": "profile_types",
    "ros2_node_profile": "profile_node",
    "fault_scenario": "scenario",
}

# A Foxglove WebSocket v1 client's messages to keel's monitor (docs/monitor.md), good and bad.
# Text frames are JSON; a service call is opcode 0x02, u32 service id, u32 call id, u32 encoding
# length, the encoding, the payload (little-endian). keel's services: 1 emergency stop, 2 clear.
TOKEN = "5f0c2a9e4b1d7c3a8e6f2b0d9a4c1e7f"
CLIENT_TEXT = {
    "subscribe": '{"op":"subscribe","subscriptions":[{"id":0,"channelId":1}]}',
    "subscribe_two": '{"op":"subscribe","subscriptions":[{"id":1,"channelId":2},{"id":2,"channelId":3}]}',
    "subscribe_none": '{"op":"subscribe","subscriptions":[]}',
    "unsubscribe": '{"op":"unsubscribe","subscriptionIds":[0,1]}',
    "get_parameters": '{"op":"getParameters","parameterNames":["/keel/rate"],"id":"get-1"}',
    "set_parameters": '{"op":"setParameters","parameters":[{"name":"/keel/rate","value":2.5}],"id":"set-1"}',
    "subscribe_parameter_updates": '{"op":"subscribeParameterUpdates","parameterNames":["/keel/rate"]}',
    "client_advertise": ('{"op":"advertise","channels":[{"id":7,"topic":"/cmd","encoding":"json",'
                         '"schemaName":"Cmd","schema":"{\\"type\\":\\"object\\"}"}]}'),
    "client_unadvertise": '{"op":"unadvertise","channelIds":[7]}',
    "subscribe_connection_graph": '{"op":"subscribeConnectionGraph"}',
    "fetch_asset": '{"op":"fetchAsset","uri":"package://keel/robot.urdf","requestId":3}',
    "bad_not_json": '{"op":"subscribe",',
    "bad_array": '[{"op":"subscribe"}]',
    "bad_op_number": '{"op":42}',
    "bad_unknown_op": '{"op":"fly","to":"moon"}',
    "bad_negative_id": '{"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]}',
    "bad_id_too_large": '{"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]}',
    "bad_string_id": '{"op":"unsubscribe","subscriptionIds":["0"]}',
    "bad_float_id": '{"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1e0}]}',
    "escaped_op": '{"op":"\\u0073ubscribe","subscriptions":[{"id":9,"channelId":1}]}',
    "nested": '{"op":"getParameters","parameterNames":[[[[{"a":[null,true,false,"\\ud83e\\udd16"]}]]]]}',
}


def service_call(service, call, encoding, payload):
    return struct.pack("<BIII", 2, service, call, len(encoding)) + encoding + payload


CLIENT_BINARY = {
    "call_emergency_stop": service_call(1, 1, b"json", b'{"token":"%s"}' % TOKEN.encode()),
    "call_clear_emergency": service_call(2, 2, b"json", b'{"token":"%s"}' % TOKEN.encode()),
    "call_no_token": service_call(1, 3, b"json", b"{}"),
    "call_unknown_service": service_call(99, 4, b"json", b'{"token":""}'),
    "call_cbor": service_call(1, 5, b"cbor", b"\xa1\x65token\x60"),
    "call_empty": service_call(1, 6, b"", b""),
    "bad_call_short": service_call(1, 7, b"json", b"")[:12],
    "bad_call_encoding_past_end": struct.pack("<BIII", 2, 1, 8, 0xFFFFFFFF) + b"json",
    "client_message_data": struct.pack("<BI", 1, 7) + b'{"x":1}',
    "bad_opcode": struct.pack("<BI", 5, 0),
}

# Bytes as they are in a message: the dictionary file escapes them.
CLIENT_DICT = [b'"op"', b'"subscribe"', b'"unsubscribe"', b'"subscriptions"', b'"subscriptionIds"', b'"id"',
               b'"channelId"', b'"channelIds"', b'"getParameters"', b'"setParameters"', b'"parameterNames"',
               b'"parameters"', b'"subscribeParameterUpdates"', b'"unsubscribeParameterUpdates"',
               b'"subscribeConnectionGraph"', b'"unsubscribeConnectionGraph"', b'"fetchAsset"', b'"advertise"',
               b'"unadvertise"', b'"token"', b'"json"', b"4294967295", b"4294967296", b"-1", b"1e3", b"null",
               b"true", b"false", b"\\u0000", b"\\ud83e\\udd16", b'":"', b'":[', b'":{', b"},{",
               struct.pack("<BI", 2, 1), struct.pack("<I", 4) + b"json"]


def dict_entry(token):
    """A libFuzzer dictionary line: printable ASCII as is, quote and backslash escaped, others \\xNN."""
    out = ""
    for byte in token:
        c = chr(byte)
        out += "\\" + c if c in '"\\' else c if 32 <= byte < 127 else "\\x%02X" % byte
    return '"%s"\n' % out


def write_client_seeds():
    folder = os.path.join("fuzz", "corpus", "monitor_client")
    os.makedirs(folder, exist_ok=True)
    for name, text in CLIENT_TEXT.items():
        with open(os.path.join(folder, "text_" + name), "wb") as out:
            out.write(b"0" + text.encode())
    for name, data in CLIENT_BINARY.items():
        with open(os.path.join(folder, "binary_" + name), "wb") as out:
            out.write(b"1" + data)
    with open("fuzz/monitor_client.dict", "w") as out:
        out.write("# libFuzzer dictionary for the monitor_client target: the Foxglove WebSocket v1 client\n"
                  "# protocol's JSON ops and keys, edge numbers, and a service call's header words. Made by\n"
                  "# fuzz/make_seeds.py.\n")
        for token in CLIENT_DICT:
            out.write(dict_entry(token))
    print("monitor_client: %d seeds" % (len(CLIENT_TEXT) + len(CLIENT_BINARY)))


def main():
    os.chdir(ROOT)
    elements, attributes, values = set(), set(), set()
    by_target = {}
    for base in ["tests", "robot", "examples", "components", "bench", "third_party"]:
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
    write_client_seeds()


if __name__ == "__main__":
    main()
