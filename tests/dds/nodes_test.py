#!/usr/bin/env python3
"""ROS 2 nodes under keel's rules, against real rclpy nodes (ROS 2 Kilted from PyPI, Fast DDS):
ordinary nodes (tests/dds/nodes/), knowing nothing of keel, started by `keel run` from node
profiles (docs/ros2-nodes.md), watched, restarted and stopped by it.

  nodes_test.py KEEL_CLI [unittest options]

Each test runs on a ROS_DOMAIN_ID of its own, pinned to the loopback (tests/dds/*-lo.xml), with
the test peers' venv (scripts/peers.sh): its python3 is the nodes' (put first on their PATH by
their profiles' <environment>)."""
import os
import signal
import sys
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ros2_peer_test as peers  # noqa: E402
from domains import domain  # noqa: E402
from std_msgs.msg import String  # noqa: E402

HERE = Path(__file__).resolve().parent
VENV_BIN = str(Path(sys.executable).parent)


def node_profile(name, command, node, parameters=(), ports=""):
    params = "".join(f'<parameter name="{k}">{v}</parameter>' for k, v in parameters)
    return (f'<?xml version="1.0"?>\n<ros2_node_profile><name>{name}</name><command>{command}</command>'
            f"<node>{node}</node>"
            f'<environment><variable name="PATH" value="{VENV_BIN}:{os.environ.get("PATH", "")}"/></environment>'
            f"<parameters>{params}</parameters><stop grace=\"2000\"/><ports>{ports}</ports></ros2_node_profile>\n")


TALKER = node_profile("Talker", "python3 talker.py", "/demo/talker", [("greeting", "hi")],
                      "<data_port><name>chatter</name><usage>output</usage><data_type>std_msgs/msg/String</data_type>"
                      "<topic>/demo/chatter</topic></data_port>")


def package(name="nodes_test", ref="talker.xml", policy="<severity>reset</severity>"):
    return (f'<?xml version="1.0"?>\n<package_profile><name>{name}</name><subcomponents><subcomponent>'
            f"<name>talker</name><reference>{ref}</reference><fault_policy>{policy}</fault_policy>"
            f"</subcomponent></subcomponents></package_profile>\n")


def run_with_talker(test, d, **kw):
    # talker.py beside its profile, from whose folder it runs.
    files = {"talker.xml": TALKER, "talker.py": (HERE / "nodes" / "talker.py").read_text()}
    return peers.KeelRun(test, d, package(), files, **kw)


def gone(pid):
    """No such process, or a zombie nobody reaped yet (an orphan's parent may be a container's init)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state == "Z"


def wait_until(pred, seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.02)
    return pred()


class Supervised(unittest.TestCase):
    def test_keel_starts_the_node_by_its_name_and_parameter_and_restarts_it_after_a_kill_9(self):
        """The node publishes as /demo/talker with greeting "hi" (keel's command line), is in the
        graph beside keel's own node; killed with kill -9 it is a `process` fault of `talker`,
        restarted as a new process that publishes again."""
        d = domain()
        run = run_with_talker(self, d)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20,
                                 "the node's start")
        self.assertEqual(started["component"], "talker")
        self.assertEqual(started["node"], "/demo/talker")
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(String, "/demo/chatter", lambda m: heard.append(m.data), 10)
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("hi ") for h in heard), 30), f"heard: {heard}")
        nodes = peer.node.get_node_names_and_namespaces()
        self.assertIn(("talker", "/demo"), nodes)
        self.assertIn(("nodes_test", "/keel"), nodes)

        # It prints "talker up" right after its first message: killed before that, its output
        # would hold one line fewer than its lives.
        out_file = run.dir / "log.talker.out"
        self.assertTrue(wait_until(lambda: "talker up" in out_file.read_text(), 30), out_file.read_text())
        os.kill(started["pid"], signal.SIGKILL)
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 20,
                               "the node's death as a fault")
        self.assertEqual(fault["kind"], "process")
        self.assertIn(f"node '/demo/talker' (pid {started['pid']}) killed by signal 9 (SIGKILL)", fault["detail"])
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "the node's restart")
        self.assertNotEqual(again["pid"], started["pid"])
        run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"], 20,
                     "the fault's recovery")
        # The new process says "talker up" once it has published; spinning until then also takes
        # what the old one sent before its death. Every message after that is the new process's
        # (not necessarily its first: a volatile subscription misses what a new writer sends
        # before they match).
        self.assertTrue(peer.spin_until(lambda: out_file.read_text().count("talker up") == 2, 30),
                        out_file.read_text())
        heard.clear()
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("hi ") for h in heard), 30),
                        f"the new process was not heard: {heard}")
        run.stop()
        stopped = [r for r in run.records() if r.get("event") == "node" and r.get("phase") == "stopped"]
        self.assertEqual([r["pid"] for r in stopped], [again["pid"]], run.records())
        self.assertTrue(gone(again["pid"]))
        output = (run.dir / "log.talker.out").read_text()
        self.assertEqual(output.count("talker up"), 2, output)
        # keel run's summary: the node, its two starts, its one exit by itself, its output file.
        line = next((l for l in run.output.splitlines() if l.startswith("talker ") and "/demo/talker" in l), "")
        self.assertEqual(line.split(), ["talker", "/demo/talker", "2", "1", str(run.dir / "log.talker.out")],
                         run.output)
        self.assertNotIn("it ended by itself", run.output)  # it was stopped by keel last

    def test_no_node_outlives_keel_run_killed_with_kill_9(self):
        """kill -9 of keel run: its node dies too (keel-node-exec's PR_SET_PDEATHSIG)."""
        d = domain()
        run = run_with_talker(self, d)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20,
                                 "the node's start")
        run.proc.kill()
        run.proc.wait()
        self.assertTrue(wait_until(lambda: gone(started["pid"]), 20), "the node outlived keel run's kill -9")

    def test_a_node_that_exits_at_once_is_a_process_fault_with_its_status_and_last_lines(self):
        """A node that cannot start (its device is missing) exits at once: a `process` fault with
        its exit status and its last line, and its last lines in the log; not a hang."""
        d = domain()
        failing = node_profile("Broken", "python3 -c \"import sys; print('opening /dev/ttyUSB0'); "
                               "sys.exit('no sonar on /dev/ttyUSB0')\"", "/broken")
        run = peers.KeelRun(self, d, package(ref="broken.xml", policy="<severity>stop</severity>"),
                            {"broken.xml": failing})
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the node's exit as a fault")
        self.assertEqual(fault["kind"], "process")
        self.assertIn("exited with status 1: no sonar on /dev/ttyUSB0", fault["detail"])
        [exited] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "exited", 10, "its record")
        self.assertEqual(exited["last_lines"], ["opening /dev/ttyUSB0", "no sonar on /dev/ttyUSB0"])
        run.stop()
        self.assertIn("  it ended by itself: exited with status 1; its last lines:\n"
                      "  | opening /dev/ttyUSB0\n  | no sonar on /dev/ttyUSB0\n", run.output)


if __name__ == "__main__":
    peers.KEEL, peers.COMPONENTS = sys.argv[1], ""  # no component libraries: nodes only
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = str(HERE / "fastdds-lo.xml")
    unittest.main(argv=[sys.argv[0]] + sys.argv[2:], verbosity=2)
