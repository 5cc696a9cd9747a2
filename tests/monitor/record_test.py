"""keel run --record FILE.mcap, read by an independent implementation: PyPI's mcap reader.

Runs examples/02 with its faults injected and --log beside --record: the recording holds every
record of the log on /keel/faults and the state on /keel/state. Then the same run killed with
kill -9: the cut recording reads up to the cut, and holds every record written more than a
second before the kill.

And a counter sending 10,000 values a second: the recording holds every one of them.

    tests/peers/venv/bin/python tests/monitor/record_test.py KEEL TEST_COMPONENT_DIR
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

from mcap.reader import make_reader
from mcap.stream_reader import StreamReader

from mcap_cut import messages_up_to_the_cut

KEEL = sys.argv.pop(1) if len(sys.argv) > 1 else "build/bin/keel"
TEST_COMPONENTS = sys.argv.pop(1) if len(sys.argv) > 1 else "build/tests/components"
REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
APP = os.path.join(REPO, "examples/02_fault_detection")
TEN_KHZ = os.path.join(REPO, "tests/integration/profiles/monitor/ten_khz.xml")


def log_records(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.endswith("\n")]


class Record(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.mcap = os.path.join(self.dir.name, "run.mcap")
        self.log = os.path.join(self.dir.name, "run.jsonl")

    def tearDown(self):
        self.dir.cleanup()

    def keel(self, *extra):
        return [KEEL, "run", f"{APP}/app.xml", "--inject", f"{APP}/scenario.xml", "--log", self.log,
                "--record", self.mcap, *extra]

    def test_a_whole_run_is_every_log_record_and_the_state_indexed(self):
        subprocess.run(self.keel("--duration", "2.5"), check=True, capture_output=True, cwd=REPO)
        with open(self.mcap, "rb") as f:
            reader = make_reader(f, validate_crcs=True)
            summary = reader.get_summary()
            self.assertGreater(len(summary.chunk_indexes), 0, "indexed: chunk indexes in the summary")
            schemas = {s.id: s for s in summary.schemas.values()}
            self.assertEqual({s.encoding for s in schemas.values()}, {"jsonschema"})
            messages = [(c.topic, m.log_time, json.loads(m.data)) for _, c, m in reader.iter_messages()]
        faults = [r for topic, _, r in messages if topic == "/keel/faults"]
        self.assertEqual(faults, log_records(self.log), "every log record, in order, as written")
        counts = summary.statistics.channel_message_counts
        self.assertEqual(sum(counts.values()), len(messages))
        states = [r for topic, _, r in messages if topic == "/keel/state"]
        self.assertGreaterEqual(len(states), 2, "a snapshot at the start and on changes")
        left = next(c for c in states[-1]["components"] if c["name"] == "sonar_left")
        self.assertEqual(left["faults"], 1, "the segfault counted")
        self.assertTrue(any(r["event"] == "detected" and r["component"] == "sonar_left" for r in faults))
        # Log times are Unix ns: the record's t_ns past the run's start, recorded in the metadata.
        start = None
        with open(self.mcap, "rb") as f:
            for record in StreamReader(f).records:
                if type(record).__name__ == "Metadata" and record.name == "keel":
                    start = int(record.metadata["start_unix_ns"])
        self.assertIsNotNone(start)
        for topic, log_time, r in messages:
            if topic == "/keel/faults":
                self.assertEqual(log_time, start + r["t_ns"])

    def test_a_recording_cut_by_kill_9_keeps_all_but_the_last_second(self):
        keel = subprocess.Popen(self.keel("--duration", "60"), stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, cwd=REPO)
        time.sleep(3.0)  # the faults come at 0.3-1.7 s: more than a second before the kill
        os.kill(keel.pid, signal.SIGKILL)
        killed_wall = time.time_ns()
        keel.wait()
        logged = log_records(self.log)  # whole up to the kill (docs/kill-9.md)
        with open(self.mcap, "rb") as f:
            start = next(int(r.metadata["start_unix_ns"]) for r in StreamReader(f).records
                         if type(r).__name__ == "Metadata")
        killed_at = killed_wall - start  # on the run's clock
        messages = [(t, lt, json.loads(d)) for t, lt, d in messages_up_to_the_cut(self.mcap)]
        recorded = [r for topic, _, r in messages if topic == "/keel/faults"]
        states = [log_time for topic, log_time, _ in messages if topic == "/keel/state"]
        # A snapshot a second, and at most the last second lost.
        self.assertGreater(max(states) - start, killed_at - 2.2e9, "a state from before the last second")
        self.assertGreater(len(recorded), 0)
        self.assertEqual(recorded, logged[: len(recorded)], "what is there is the log, in order")
        older = [r for r in logged if r["t_ns"] < killed_at - 1.2e9]
        self.assertGreaterEqual(len(recorded), len(older),
                                f"records more than a second older than the kill: {len(older)}, recorded {len(recorded)}")
        with open(self.mcap, "rb") as f:
            with self.assertRaises(Exception, msg="no footer: not a complete file"):
                make_reader(f).get_summary()


    def test_ten_thousand_port_values_a_second_are_all_recorded(self):
        env = dict(os.environ, KEEL_COMPONENT_PATH=os.path.abspath(TEST_COMPONENTS))
        subprocess.run([KEEL, "run", TEN_KHZ, "--duration", "3", "--log", self.log, "--record", self.mcap],
                       check=True, capture_output=True, cwd=REPO, env=env)
        with open(self.mcap, "rb") as f:
            reader = make_reader(f, validate_crcs=True)
            values = [json.loads(m.data)["value"]
                      for _, _, m in reader.iter_messages(topics=["/keel/ports/counter/count"])]
            self.assertEqual(reader.get_summary().statistics.channel_message_counts[
                next(c.id for c in reader.get_summary().channels.values() if c.topic == "/keel/ports/counter/count")],
                len(values))
        sent = next(r["executions"] for r in log_records(self.log)
                    if r["event"] == "counts" and r.get("component") == "counter")
        # At 10 kHz for 3 s; a machine busy with other tests sends fewer, and the point is that
        # whatever was sent at such a rate is recorded (the benchmark times the full rate alone).
        self.assertGreater(sent, 3 * 5000, "at least 5,000 values a second for 3 s")
        self.assertEqual(len(values), sent, "every value the counter sent")
        self.assertEqual(values, list(range(1, sent + 1)), "in order, none twice")


if __name__ == "__main__":
    unittest.main(verbosity=2)
