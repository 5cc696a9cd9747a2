#!/usr/bin/env python3
"""keel's MCAP writer and reader against PyPI's `mcap` 1.6.0, an implementation independent of
keel's (installed by scripts/peers.sh in tests/peers/venv; run with that venv's python):

(a) PyPI's seeking reader reads a file keel wrote: messages, topics, JSON Schemas, statistics,
    chunk indexes and the Message Index records after each chunk, with CRCs validated;
(b) PyPI's stream reader reads copies of it cut by a kill -9 (the recipe of
    docs/lab-notes/monitor-research.md §3.4) and gets exactly the messages of the whole chunks
    before the cut, as keel's own reader does;
(c) keel's reader reads files PyPI's writer wrote uncompressed, and names the compression of one
    it cannot read.

usage: mcap_peer_test.py KEEL_MCAP_TOOL"""
import json
import pathlib
import struct
import subprocess
import sys
import tempfile
from collections import Counter

from mcap.reader import make_reader
from mcap.records import Chunk, DataEnd, Footer, MessageIndex
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from mcap_cut import messages_up_to_the_cut

T0 = 1_700_000_000_000_000_000  # the tool's first log time, ns
TOPICS = ["/keel/faults", "/keel/state", "/keel/ports/arm/pose"]  # message i is on TOPICS[i % 3]
PER_CHUNK = 7  # the tool flushes a chunk every 7 messages
N = 40


class Checks:
    def __init__(self):
        self.failures = []

    def __call__(self, cond, what):
        if not cond:
            self.failures.append(what)
        return cond


def tool(*args, ok=True):
    r = subprocess.run([sys.argv[1], *map(str, args)], capture_output=True, text=True, timeout=60)
    if ok and r.returncode != 0:
        raise SystemExit(f"keel_mcap_tool {' '.join(map(str, args))}: exit {r.returncode}: {r.stderr}")
    return r


def keel_reads(path):
    """keel's reader, through the tool: [(topic, log_time, payload bytes)], and its last line."""
    lines = [json.loads(line) for line in tool("read", path).stdout.splitlines()]
    return [(m["topic"], m["log_time"], m["payload"].encode()) for m in lines[:-1]], lines[-1]


def pypi_reads_keels_file(path, check):
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        header = reader.get_header()
        check(header.profile == "" and header.library == "keel mcap_tool", f"header: {header}")
        summary = reader.get_summary()
        messages = list(reader.iter_messages())
        check(len(messages) == N, f"(a) {len(messages)} messages, not {N}")
        for i, (schema, channel, message) in enumerate(messages):
            check(channel.topic == TOPICS[i % 3], f"(a) message {i} on {channel.topic}")
            check(message.log_time == T0 + i * 1_000_000, f"(a) message {i} at {message.log_time}")
            check(json.loads(message.data) == {"i": i, "channel": channel.id}, f"(a) message {i}: {message.data}")
            check(schema.encoding == "jsonschema" and channel.message_encoding == "json",
                  f"(a) encodings {schema.encoding} {channel.message_encoding}")
            check(schema.name == ("keel.State" if i % 3 == 1 else "keel.Fault"), f"(a) schema {schema.name}")
            json.loads(schema.data)  # a JSON Schema is JSON
        faults = list(reader.iter_messages(topics=["/keel/faults"]))
        check(len(faults) == (N + 2) // 3, f"(a) {len(faults)} /keel/faults messages through the chunk indexes")
        check(sorted(c.topic for c in summary.channels.values()) == sorted(TOPICS), f"(a) channels {summary.channels}")
        check(len(summary.schemas) == 2, f"(a) {len(summary.schemas)} schemas, not 2 (two channels share one)")
        stats = summary.statistics
        counts = {i + 1: len(range(i, N, 3)) for i in range(3)}
        check(stats.message_count == N and stats.channel_message_counts == counts,
              f"(a) statistics {stats.message_count} {stats.channel_message_counts}, not {N} {counts}")
        chunks = (N + PER_CHUNK - 1) // PER_CHUNK
        check(stats.chunk_count == chunks and len(summary.chunk_indexes) == chunks,
              f"(a) {stats.chunk_count} chunks, {len(summary.chunk_indexes)} chunk indexes, not {chunks}")
        check(stats.message_start_time == T0 and stats.message_end_time == T0 + (N - 1) * 1_000_000,
              f"(a) statistics times {stats.message_start_time} {stats.message_end_time}")
        check(all(c.compression == "" for c in summary.chunk_indexes), "(a) a compressed chunk")
        metadata = list(reader.iter_metadata())
        check([(m.name, m.metadata) for m in metadata] == [("keel", {"profile": "robot.xml", "keel_version": "0.1.0"})],
              f"(a) metadata {metadata}")
    return summary


def message_indexes_point_at_messages(path, summary, check):
    """The stream reader validates the data section CRC; the Message Index after each chunk lists
    every message of it, at the offset of a Message record with that log time."""
    with open(path, "rb") as f:
        records = list(StreamReader(f, emit_chunks=True, validate_crcs=True).records)
    check(any(isinstance(r, DataEnd) and r.data_section_crc != 0 for r in records), "(a) no data section CRC")
    check(isinstance(records[-1], Footer), "(a) no footer")
    chunk, seen = None, []
    for r in records:
        if isinstance(r, Chunk):
            chunk = r
            check(r.compression == "" and r.uncompressed_crc != 0, "(a) a chunk compressed or without CRC")
            seen.append(Counter())
        elif isinstance(r, MessageIndex):
            for log_time, offset in r.records:
                opcode, _, channel, _, at = struct.unpack_from("<BQHIQ", chunk.data, offset)
                check(opcode == 0x05 and channel == r.channel_id and at == log_time,
                      f"(a) message index entry {log_time},{offset} points at {opcode},{channel},{at}")
            seen[-1][r.channel_id] += len(r.records)
    per_chunk = [min(PER_CHUNK, N - k) for k in range(0, N, PER_CHUNK)]
    check([sum(c.values()) for c in seen] == per_chunk, f"(a) message indexes list {seen}, not {per_chunk}")
    check(len(seen) == len(summary.chunk_indexes), "(a) chunks and chunk indexes differ")


def cut_copies_give_the_whole_chunks(path, summary, tmp, check):
    data = path.read_bytes()
    everything = messages_up_to_the_cut(path)
    check(len(everything) == N, f"(b) the uncut file gives {len(everything)} messages")
    ends = [c.chunk_start_offset + c.chunk_length for c in summary.chunk_indexes]
    cuts = [c.chunk_start_offset + c.chunk_length // 2 for c in summary.chunk_indexes]  # inside each chunk
    cuts += [ends[1], ends[1] + 3, summary.chunk_indexes[0].chunk_start_offset, len(data) // 2, len(data) - 1]
    for cut in cuts:
        cut_path = tmp / f"cut_{cut}.mcap"
        cut_path.write_bytes(data[:cut])
        whole = sum(1 for c in summary.chunk_indexes if c.chunk_start_offset + c.chunk_length <= cut)
        expected = [m for m in everything if any(
            c.message_start_time <= m[1] <= c.message_end_time for c in summary.chunk_indexes[:whole])]
        got = messages_up_to_the_cut(cut_path)
        check(got == expected, f"(b) PyPI, cut at {cut}: {len(got)} messages, not the {len(expected)} of "
                               f"{whole} whole chunks")
        keel, end = keel_reads(cut_path)
        check(keel == expected, f"(b) keel, cut at {cut}: {len(keel)} messages, not {len(expected)}")
        check(not end["complete"] and end["stopped_at"], f"(b) keel, cut at {cut}: {end}")


def pypi_writes(path, check, compression=CompressionType.NONE, data_crcs=False):
    """A file from PyPI's writer: two channels (one without a schema), small chunks, metadata."""
    with open(path, "wb") as f:
        w = Writer(f, chunk_size=256, compression=compression, enable_data_crcs=data_crcs)
        w.start(profile="", library="pypi mcap")
        schema = w.register_schema("py.Thing", "jsonschema", b'{"type":"object"}')
        a = w.register_channel("/py/a", "json", schema)
        b = w.register_channel("/py/raw", "json", 0)
        w.add_metadata("run", {"robot": "r1", "operator": "test"})
        written = []
        for i in range(30):
            channel, topic = (a, "/py/a") if i % 4 else (b, "/py/raw")
            payload = json.dumps({"n": i, "text": "é\"\\"}).encode()
            w.add_message(channel, log_time=T0 + 10 * i, data=payload, publish_time=T0 + 10 * i, sequence=i)
            written.append((topic, T0 + 10 * i, payload))
        w.finish()
    return written


def keel_reads_pypis_files(tmp, check):
    for data_crcs in (False, True):
        path = tmp / f"pypi_{data_crcs}.mcap"
        written = pypi_writes(path, check, data_crcs=data_crcs)
        with open(path, "rb") as f:
            chunks = [r for r in StreamReader(f, emit_chunks=True).records if isinstance(r, Chunk)]
        check(len(chunks) > 1 and all(c.compression == "" for c in chunks), f"(c) PyPI wrote {len(chunks)} chunks")
        got, end = keel_reads(path)
        check(got == written, f"(c) keel read {got[:3]}..., PyPI wrote {written[:3]}...")
        check(end["complete"] and end["stopped_at"] == "", f"(c) keel: {end}")
        check(end["library"] == "pypi mcap", f"(c) library {end['library']}")
        channels = {c["topic"]: c for c in end["channels"]}
        check(channels.get("/py/a", {}).get("schema_name") == "py.Thing"
              and channels.get("/py/raw", {}).get("schema_name") == "", f"(c) channels {end['channels']}")
        check(end["metadata"] == [{"name": "run", "values": {"robot": "r1", "operator": "test"}}],
              f"(c) metadata {end['metadata']}")
    path = tmp / "pypi_zstd.mcap"
    pypi_writes(path, check, compression=CompressionType.ZSTD)
    r = tool("read", path, ok=False)
    check(r.returncode == 1 and "compressed with zstd: keel reads uncompressed MCAP only" in r.stderr,
          f"(c) a zstd file: exit {r.returncode}, {r.stderr!r}")


def main():
    check = Checks()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        path = tmp / "keel.mcap"
        wrote = json.loads(tool("write", path, N).stdout)
        check(wrote == {"messages": N, "bytes": path.stat().st_size}, f"the tool says {wrote}")
        summary = pypi_reads_keels_file(path, check)
        message_indexes_point_at_messages(path, summary, check)
        cut_copies_give_the_whole_chunks(path, summary, tmp, check)
        keel_reads_pypis_files(tmp, check)
    for f in check.failures:
        print("FAIL:", f)
    print("mcap_peer_test:", "FAILED" if check.failures else "ok")
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
