#!/usr/bin/env python3
"""ROS 2 nodes under keel's rules, against real rclpy nodes (ROS 2 Kilted from PyPI, Fast DDS):
ordinary nodes (tests/dds/nodes/), knowing nothing of keel, started by `keel run` from node
profiles (docs/ros2-nodes.md), watched, restarted and stopped by it.

  nodes_test.py KEEL_CLI COMPONENT_DIR [unittest options]

Each test runs on a ROS_DOMAIN_ID of its own, pinned to the loopback (tests/dds/*-lo.xml), with
the test peers' venv (scripts/peers.sh): its python3 is the nodes' (put first on their PATH by
their profiles' <environment>)."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ros2_peer_test as peers  # noqa: E402
from domains import domain  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus  # noqa: E402
from geometry_msgs.msg import Twist  # noqa: E402
from std_msgs.msg import String  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.parameter_client import AsyncParameterClient  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
VENV_BIN = str(Path(sys.executable).parent)


def node_profile(name, command, node, parameters=(), ports="", start_ms=None, extra=""):
    """`extra`: more of the profile's elements (<lifecycle/>), before its ports."""
    params = "".join(f'<parameter name="{k}">{v}</parameter>' for k, v in parameters)
    start = f'<start timeout="{start_ms}"/>' if start_ms else ""
    return (f'<?xml version="1.0"?>\n<ros2_node_profile><name>{name}</name><command>{command}</command>'
            f"<node>{node}</node>"
            f'<environment><variable name="PATH" value="{VENV_BIN}:{os.environ.get("PATH", "")}"/></environment>'
            f"<parameters>{params}</parameters>{start}<stop grace=\"2000\"/>{extra}<ports>{ports}</ports>"
            "</ros2_node_profile>\n")


def string_port(name, topic, usage="output"):
    return (f"<data_port><name>{name}</name><usage>{usage}</usage><data_type>std_msgs/msg/String</data_type>"
            f"<topic>{topic}</topic></data_port>")


TALKER = node_profile("Talker", "python3 talker.py", "/demo/talker", [("greeting", "hi")],
                      string_port("chatter", "/demo/chatter"))


def package(name="nodes_test", ref="talker.xml", policy="<severity>reset</severity>", attach=False):
    return (f'<?xml version="1.0"?>\n<package_profile><name>{name}</name><subcomponents><subcomponent>'
            f"<name>talker</name><reference>{ref}</reference>{'<attach/>' if attach else ''}"
            f"<fault_policy>{policy}</fault_policy></subcomponent></subcomponents></package_profile>\n")


def start_talker(test, d, name="talker", namespace="/demo"):
    """talker.py started as `ros2 run` would, by the test: not keel's."""
    env = peers.peer_env(d)
    proc = subprocess.Popen([sys.executable, str(HERE / "nodes" / "talker.py"), "--ros-args", "-r",
                             f"__node:={name}", "-r", f"__ns:={namespace}"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def end():
        if proc.poll() is None:
            proc.kill()
        proc.wait()
    test.addCleanup(end)
    return proc


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
        # Up: its process lists /demo/talker in the graph and publishes /demo/chatter.
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the node up")
        self.assertEqual(up["pid"], started["pid"])
        self.assertGreater(up["after_ms"], 0)
        # Fast DDS announces the participant's pid: keel tells the node's lives apart by it.
        self.assertEqual([r for r in run.records() if "announces no process id" in r.get("message", "")], [])
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(String, "/demo/chatter", lambda m: heard.append(m.data), 10)
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("hi ") for h in heard), 30), f"heard: {heard}")
        # rclpy lists a node once its ros_discovery_info sample came, which can be a Fast DDS
        # heartbeat (3 s) after the first message.
        listed = {("talker", "/demo"), ("nodes_test", "/keel")}
        self.assertTrue(peer.spin_until(lambda: listed <= set(peer.node.get_node_names_and_namespaces()), 10),
                        peer.node.get_node_names_and_namespaces())

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
        # Up again: the new process, although the dead one stays in the graph until its lease
        # expires (about 20 s after a kill -9), listing the same name and topic.
        [up_again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up"
                                     and r["pid"] != started["pid"], 30, "the new process up")
        self.assertEqual(up_again["pid"], again["pid"])
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


class Deaths(unittest.TestCase):
    def test_an_uncaught_exception_and_an_exit_3_are_process_faults_restarted_with_the_parameters(self):
        """The talker dies at its 10th message, once of an uncaught exception out of its callback
        (Python's status 1, its traceback the last lines), once by sys.exit(3): each a `process`
        fault with its status and its last lines, and its reset restarts it with its parameters
        (the greeting "hi" in the params file of the `restarted` record)."""
        for how, status, last in (("exception", 1, "ZeroDivisionError: division by zero"), ("exit", 3, "talker up")):
            with self.subTest(how=how):
                talker = node_profile("Talker", "python3 talker.py", "/demo/talker",
                                      [("greeting", "hi"), ("fail_at", "10"), ("fail_how", how)],
                                      string_port("chatter", "/demo/chatter"))
                run = peers.KeelRun(self, domain(), package(),
                                    {"talker.xml": talker, "talker.py": (HERE / "nodes" / "talker.py").read_text()})
                [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                                       "its death")
                self.assertEqual(fault["kind"], "process")
                self.assertIn(f"exited with status {status}", fault["detail"])
                [exited] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "exited", 10,
                                        "its exit record")
                self.assertEqual(exited["last_lines"][-1], last, exited["last_lines"])
                [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                                       "its restart")
                self.assertIn('greeting: "hi"', Path(again["params"]).read_text())
                run.stop()


class Emergency(unittest.TestCase):
    def test_an_emergency_stops_the_node_and_publishes_its_safe_command_while_it_holds(self):
        """The talker's <emergency>: <stop/> and a Twist on /demo/cmd_vel at 20 Hz. Its kill -9 is
        handled by an emergency stop: keel stops it (no restart) and publishes the type's zero
        value on /demo/cmd_vel, heard by an ordinary rclpy subscriber, at about 20 Hz for as long
        as the emergency holds; nothing on that topic before."""
        d = domain()
        talker = TALKER.replace("<stop ", '<emergency><stop/><publish topic="/demo/cmd_vel" '
                                          'type="geometry_msgs/msg/Twist" rate="20"/></emergency><stop ')
        files = {"talker.xml": talker, "talker.py": (HERE / "nodes" / "talker.py").read_text()}
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(Twist, "/demo/cmd_vel", lambda m: heard.append((time.monotonic(), m)), 10)
        run = peers.KeelRun(self, d, package(policy="<severity>emergency</severity>"), files)
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the talker up")
        peer.spin_until(lambda: False, 1.0)  # matched; the talker publishes no Twist
        self.assertEqual(heard, [])
        os.kill(up["pid"], signal.SIGKILL)
        run.wait_for(lambda r: r.get("event") == "action" and r.get("action") == "emergency_stop", 10, "the emergency")
        self.assertTrue(peer.spin_until(lambda: len(heard) >= 1, 10), "no safe command")
        first = heard[0][0]
        peer.spin_until(lambda: False, 2.0)
        during = [t for t, _ in heard if t - first <= 2.0]
        self.assertGreaterEqual(len(during), 25, f"{len(during)} in 2 s at 20 Hz")
        self.assertLessEqual(len(during), 45, f"{len(during)} in 2 s at 20 Hz")
        zero = Twist()
        self.assertTrue(all(m == zero for _, m in heard), [m for _, m in heard if m != zero][:1])
        self.assertEqual(records_of(run, event="node", phase="restarted"), [])


class Campaign(unittest.TestCase):
    def test_every_kill_9_of_a_supervised_node_is_detected_restarted_and_logged(self):
        """KEEL_NODE_KILL_CAMPAIGN (100) kills of the talker, each once keel has it up again: every
        one an `exited` record and a `process` fault naming its pid, handled by a reset that
        restarts it as a new process, recovered; nothing else went wrong; none of the killed
        processes is left, nor the last one once keel run ends."""
        kills = int(os.environ.get("KEEL_NODE_KILL_CAMPAIGN", "100"))
        d = domain()
        files = {"talker.xml": TALKER, "talker.py": (HERE / "nodes" / "talker.py").read_text()}
        policy = '<severity>reset</severity><restart intensity="1000" period="1000"/>'
        run = peers.KeelRun(self, d, package(policy=policy), files, duration=600)
        killed = []
        for k in range(kills + 1):
            up = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up"
                              and r["pid"] not in killed, 30, f"the talker up after {k} kills")
            if k == kills:
                break
            killed.append(up[0]["pid"])
            os.kill(up[0]["pid"], signal.SIGKILL)
        last = up[0]["pid"]
        records = run.records()
        faults = [r for r in records if r.get("event") == "detected"]
        self.assertEqual([f["kind"] for f in faults], ["process"] * kills, [f["detail"] for f in faults])
        for pid, fault in zip(killed, faults):
            self.assertTrue(fault["detail"].startswith(f"node '/demo/talker' (pid {pid}) killed by signal 9"),
                            fault["detail"])
        exited = [r["pid"] for r in records if r.get("event") == "node" and r.get("phase") == "exited"]
        self.assertEqual(exited, killed)
        restarted = [r["pid"] for r in records if r.get("event") == "node" and r.get("phase") == "restarted"]
        self.assertEqual(len(restarted), kills)
        self.assertEqual(len(set(restarted) | set(killed)), kills + 1, "a restart reused a pid keel killed")
        self.assertEqual(restarted[-1], last)
        ids = {f["fault_id"] for f in faults}
        resets = {r["fault_id"] for r in records if r.get("event") == "action" and r.get("action") == "reset"
                  and r.get("outcome") == "ok"}
        recovered = {r["fault_id"] for r in records if r.get("event") == "recovered"}
        self.assertEqual(len(ids), kills)
        self.assertEqual(ids - resets, set())
        self.assertEqual(ids - recovered, set())
        self.assertTrue(all(gone(p) for p in killed))
        run.stop()
        self.assertTrue(wait_until(lambda: gone(last), 10), f"the last talker (pid {last}) outlived keel run")


class Parameters(unittest.TestCase):
    def test_a_node_restarted_after_a_kill_9_has_the_parameter_value_set_on_it_at_run_time(self):
        """The talker starts with greeting "hi" (its profile's); a parameter client sets it to
        "changed" and the node says so; killed with kill -9 and restarted by its reset, the new
        process says "changed" too: its `restarted` record names the params file it was given,
        which holds the value set."""
        d = domain()
        run = run_with_talker(self, d)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20,
                                 "the node's start")
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the node up")
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(String, "/demo/chatter", lambda m: heard.append(m.data), 10)
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("hi ") for h in heard), 30), f"heard: {heard}")

        client = AsyncParameterClient(peer.node, "/demo/talker")
        self.assertTrue(client.wait_for_services(timeout_sec=20), "the talker's parameter services")
        future = client.set_parameters([Parameter("greeting", value="changed")])
        self.assertTrue(peer.spin_until(future.done, 20), "no answer to set_parameters")
        self.assertTrue(future.result().results[0].successful, future.result())
        # The node publishes its event before it answers; keel's reader has it a moment later.
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("changed ") for h in heard), 10), heard)
        out_file = run.dir / "log.talker.out"
        self.assertTrue(wait_until(lambda: "talker up" in out_file.read_text(), 30), out_file.read_text())
        time.sleep(0.5)

        os.kill(started["pid"], signal.SIGKILL)
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "the node's restart")
        params = Path(again["params"])
        self.assertEqual(params, run.dir / "log.talker.params.yaml")
        text = params.read_text()
        self.assertIn('/demo/talker:\n  ros__parameters:\n', text)
        self.assertIn('    greeting: "changed"\n', text)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up" and r["pid"] == again["pid"], 30,
                     "the new process up")
        # Every message after its "talker up" is the new process's (nodes_test's first test says why).
        self.assertTrue(peer.spin_until(lambda: out_file.read_text().count("talker up") == 2, 30),
                        out_file.read_text())
        heard.clear()
        self.assertTrue(peer.spin_until(lambda: len(heard) >= 3, 30), f"the new process was not heard: {heard}")
        self.assertTrue(all(h.startswith("changed ") for h in heard), f"the new process says: {heard}")


class Graph(unittest.TestCase):
    def test_a_node_whose_topic_never_appears_is_a_start_fault_saying_what_was_missing(self):
        """The talker is up in the graph but never publishes a topic its profile declares: when
        its start timeout ends, a `start` fault naming that topic, and no `up` record."""
        d = domain()
        profile = node_profile("Talker", "python3 talker.py", "/demo/talker", [("greeting", "hi")],
                               string_port("chatter", "/demo/chatter") + string_port("status", "/demo/status"),
                               start_ms=3000)
        files = {"talker.xml": profile, "talker.py": (HERE / "nodes" / "talker.py").read_text()}
        run = peers.KeelRun(self, d, package(policy="<severity>stop</severity>"), files)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the start fault")
        self.assertEqual(fault["kind"], "start")
        self.assertEqual(fault["detail"], "node '/demo/talker' not up within 3000 ms: it publishes no /demo/status")
        self.assertEqual([r for r in run.records() if r.get("phase") == "up"], [])

    def test_an_attached_node_is_up_when_it_appears_and_a_remote_fault_when_it_leaves(self):
        """<attach/>: keel starts nothing; the talker someone else started is up once in the
        graph with its topic; ended with SIGINT it leaves the graph: a `remote` fault; started
        again, it is up again."""
        d = domain()
        files = {"talker.xml": TALKER}
        run = peers.KeelRun(self, d, package(attach=True, policy="<severity>stop</severity>"), files)
        self.assertEqual([r for r in run.records() if r.get("event") == "node"], [])
        talker = start_talker(self, d)
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the node up")
        self.assertEqual(up["pid"], talker.pid)
        self.assertEqual(up["node"], "/demo/talker")
        talker.send_signal(signal.SIGINT)
        talker.wait(10)
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "its leaving as a fault")
        self.assertEqual(fault["kind"], "remote")
        self.assertEqual(fault["detail"], "node '/demo/talker' left the ROS 2 graph")
        again = start_talker(self, d)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up" and r["pid"] == again.pid, 30,
                     "the node up again")

    def test_an_attached_node_that_never_appears_is_a_start_fault(self):
        d = domain()
        profile = node_profile("Talker", "python3 talker.py", "/demo/talker", ports=string_port("chatter", "/x"),
                               start_ms=1500)
        run = peers.KeelRun(self, d, package(attach=True, policy="<severity>stop</severity>"),
                            {"talker.xml": profile})
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the start fault")
        self.assertEqual(fault["kind"], "start")
        self.assertEqual(fault["detail"], "node '/demo/talker' not in the ROS 2 graph within 1500 ms")


def sonar_profile(parameters=(), validity="", deadline_ms=None, diagnostics=False, start_ms=None):
    deadline = f"<deadline>{deadline_ms}</deadline>" if deadline_ms else ""
    port = ("<data_port><name>range</name><usage>output</usage><data_type>sensor_msgs/msg/Range</data_type>"
            f"<topic>/demo/range</topic>{deadline}{validity}</data_port>")
    profile = node_profile("Sonar", "python3 sonar.py", "/demo/sonar", parameters, port, start_ms)
    if diagnostics:  # its own status, named as sonar.py publishes it
        profile = profile.replace("<stop ", '<diagnostics name="sonar: driver"/><stop ')
    return profile


def sonar_files(profile):
    return {"sonar.xml": profile, "sonar.py": (HERE / "nodes" / "sonar.py").read_text()}


def records_of(run, **fields):
    return [r for r in run.records() if all(r.get(k) == v for k, v in fields.items())]


def talker_and_recorder(rec, talker_policy=""):
    """A package of the talker (its <fault_policy> body: `talker_policy`) whose chatter port is
    connected to a keel component, Recorder, appending each string it hears to `rec`."""
    policy = f"<fault_policy>{talker_policy}</fault_policy>" if talker_policy else ""
    return ('<?xml version="1.0"?>\n<package_profile><name>nodes_test</name><subcomponents>'
            f"<subcomponent><name>talker</name><reference>talker.xml</reference>{policy}</subcomponent>"
            "<subcomponent><name>recorder</name><reference>Recorder.xml</reference>"
            f'<properties><property name="path">{rec}</property></properties></subcomponent>'
            '</subcomponents><port_connections><port_connection port_type="data">'
            '<source component_name="talker" port_name="chatter"/>'
            '<target component_name="recorder" port_name="heard"/></port_connection></port_connections>'
            "</package_profile>\n")


RECORDER = peers.component_profile("Recorder", [("heard", "input", "std_msgs/msg/String")],
                                   properties='<property name="path" type="string">?</property>')


class Topics(unittest.TestCase):
    def test_a_nodes_values_reach_a_keel_component_and_another_writers_do_not(self):
        """The talker's /demo/chatter is its stand-in's output port, connected to a keel
        component (Recorder): every line it records is the talker's; an impostor publishing on
        the same topic from another process is not the node, and is not heard."""
        d = domain()
        rec = Path(tempfile.mkdtemp(prefix="keel_rec_")) / "heard.txt"
        files = {"talker.xml": TALKER, "talker.py": (HERE / "nodes" / "talker.py").read_text(), "Recorder.xml": RECORDER}
        run = peers.KeelRun(self, d, talker_and_recorder(rec), files)
        peer = peers.Ros2Peer(self, d)
        impostor = peer.node.create_publisher(String, "/demo/chatter", 10)
        self.assertTrue(wait_until(lambda: rec.exists() and rec.read_text().count(" hi ") >= 1, 30),
                        "the node's values did not reach the component")
        for i in range(40):
            impostor.publish(String(data=f"impostor {i}"))
            peer.executor.spin_once(timeout_sec=0.025)
        self.assertTrue(wait_until(lambda: rec.read_text().count(" hi ") >= 20, 30), rec.read_text())
        lines = rec.read_text().splitlines()
        self.assertEqual([l for l in lines if "impostor" in l], [])
        self.assertEqual([l for l in lines if l.split(" ", 1)[1].split(" ")[0] != "hi"], [])

    def test_a_keel_components_values_reach_a_nodes_input_topic(self):
        """A keel component (Announcer: "keel <n>" every 50 ms) connected to the echo node's input
        port: keel publishes its values on the node's input topic, /e/in; the node answers each on
        /e/out, its output port, which a Recorder in keel hears: "echo: keel <n>"."""
        d = domain()
        rec = Path(tempfile.mkdtemp(prefix="keel_rec_")) / "heard.txt"
        ports = string_port("in", "/e/in", "input") + string_port("out", "/e/out")
        echo = node_profile("Echo", "python3 echo.py", "/e/echo", (), ports)
        app = ('<?xml version="1.0"?>\n<package_profile><name>nodes_test</name><subcomponents>'
               "<subcomponent><name>announcer</name><reference>Announcer.xml</reference>"
               '<properties><property name="who">keel</property></properties></subcomponent>'
               "<subcomponent><name>echo</name><reference>echo.xml</reference></subcomponent>"
               "<subcomponent><name>recorder</name><reference>Recorder.xml</reference>"
               f'<properties><property name="path">{rec}</property></properties></subcomponent></subcomponents>'
               '<port_connections><port_connection port_type="data">'
               '<source component_name="announcer" port_name="said"/><target component_name="echo" port_name="in"/>'
               '</port_connection><port_connection port_type="data">'
               '<source component_name="echo" port_name="out"/><target component_name="recorder" port_name="heard"/>'
               "</port_connection></port_connections></package_profile>\n")
        files = {"echo.xml": echo, "echo.py": (HERE / "nodes" / "echo.py").read_text(), "Recorder.xml": RECORDER,
                 "Announcer.xml": peers.component_profile("Announcer", [("said", "output", "std_msgs/msg/String")], 50,
                                                          '<property name="who" type="string">?</property>')}
        run = peers.KeelRun(self, d, app, files)
        self.assertEqual(records_of(run, event="warning"), [])
        self.assertTrue(wait_until(lambda: rec.exists() and rec.read_text().count("echo: keel ") >= 5, 30),
                        "the node's answers did not come back: " + (rec.read_text() if rec.exists() else "nothing"))
        numbers = [int(line.rsplit(" ", 1)[1]) for line in rec.read_text().splitlines()]
        self.assertEqual(numbers, sorted(numbers), "in the order keel sent them")

    def test_a_node_that_stalls_alive_misses_its_deadline_and_is_restarted(self):
        """The sonar stops publishing after its 100th message (5 s) but stays alive: its topic's
        deadline (300 ms) is a `remote` fault of the node; reset restarts it, a new process. (Its
        deadline counts from its first sample keel heard: a stall before keel's reader matched
        the node's writer, a second after its start under ASan, would raise nothing.)"""
        d = domain()
        run = peers.KeelRun(self, d, package(ref="sonar.xml"),
                            sonar_files(sonar_profile([("stall_at", "100")], deadline_ms=300)))
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the missed deadline")
        self.assertEqual(fault["kind"], "remote")
        self.assertEqual(fault["detail"], "no sample on /demo/range within its deadline of 300 ms")
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "its restart")
        self.assertNotEqual(again["pid"], started["pid"])

    def test_a_node_up_that_never_publishes_misses_its_first_sample_by_its_start_timeout(self):
        """The sonar creates its publisher (it is up: its topic is in the graph) but never
        publishes (a driver waiting on a device that never answers). Its topic's deadline counts
        from its first sample, so its first sample is due by its start timeout (2 s): a `remote`
        fault of the node then, not before, and its reset restarts it."""
        d = domain()
        run = peers.KeelRun(self, d, package(ref="sonar.xml"),
                            sonar_files(sonar_profile([("stall_at", "0")], deadline_ms=300, start_ms=2000)))
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 20, "the node up")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the missing first sample")
        self.assertEqual(fault["kind"], "remote")
        self.assertEqual(fault["detail"], "no sample on /demo/range since the node started, within its start timeout")
        [started] = records_of(run, event="node", phase="started")
        self.assertGreater(fault["t_ns"] - started["t_ns"], 2_000_000_000)
        again = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20, "its restart")
        self.assertNotEqual(again[0]["pid"], up["pid"])

    def test_a_killed_node_is_one_fault_not_also_its_topics_deadline(self):
        """kill -9 of the sonar: its `process` fault; its topic's deadline, missed while it is
        dead, restarting and warming up (its first message a second after its start, long after
        keel restarted it), raises nothing more: the new life is timed from its own first sample."""
        d = domain()
        run = peers.KeelRun(self, d, package(ref="sonar.xml"),
                            sonar_files(sonar_profile([("warm_up_s", "1.0")], deadline_ms=300)))
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the node up")
        time.sleep(1.5)  # its first life's samples flowing
        os.kill(up["pid"], signal.SIGKILL)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up" and r["pid"] != up["pid"], 30,
                     "the new process up")
        time.sleep(2.0)  # past its warm-up, more than three deadlines after
        faults = records_of(run, event="detected", component="talker")
        self.assertEqual([f["kind"] for f in faults], ["process"], faults)

    def test_a_killed_nodes_subscriber_in_keel_loses_its_writer_at_once_not_at_its_deadline(self):
        """A keel component subscribes to the talker's topic with a 5 s deadline and a 10 s
        lease. kill -9 of the talker: the subscriber's `remote` fault comes with the node's
        death (its writer's process died), long before either; one fault for the outage, which
        ends with the restarted talker's first sample."""
        d = domain()
        rec = Path(tempfile.mkdtemp(prefix="keel_rec_")) / "heard.txt"
        app = ('<?xml version="1.0"?>\n<package_profile><name>nodes_test</name><subcomponents>'
               "<subcomponent><name>talker</name><reference>talker.xml</reference>"
               "<fault_policy><severity>reset</severity></fault_policy></subcomponent>"
               "<subcomponent><name>recorder</name><reference>Recorder.xml</reference>"
               f'<properties><property name="path">{rec}</property></properties>'
               "<fault_policy><severity>ignore</severity></fault_policy></subcomponent>"
               '</subcomponents><dds><subscribe component="recorder" port="heard" topic="/demo/chatter" '
               'type="std_msgs/msg/String" deadline="5000" liveliness="10000"/></dds></package_profile>\n')
        talker = node_profile("Talker", "python3 talker.py", "/demo/talker", [("greeting", "hi"), ("deadline_ms", "5000")],
                              string_port("chatter", "/demo/chatter"))
        files = {"talker.xml": talker, "talker.py": (HERE / "nodes" / "talker.py").read_text(),
                 "Recorder.xml": RECORDER}
        run = peers.KeelRun(self, d, app, files)
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the talker up")
        self.assertTrue(wait_until(lambda: rec.exists() and rec.read_text().count(" hi ") >= 3, 30),
                        "the subscriber heard nothing")
        os.kill(up["pid"], signal.SIGKILL)
        [died] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 10,
                              "the talker's death")
        [lost] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "recorder", 10,
                              "the subscriber's fault")
        self.assertEqual((died["kind"], lost["kind"]), ("process", "remote"))
        self.assertTrue(lost["detail"].startswith(
            f"the writer of /demo/chatter died: node '/demo/talker' (pid {up['pid']}) killed by signal 9"), lost["detail"])
        self.assertLess(lost["t_ns"] - died["t_ns"], 2_000_000_000, "not before the 5 s deadline")
        run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == lost["fault_id"], 30,
                     "the outage's end with the new talker's samples")
        faults = records_of(run, event="detected", component="recorder")
        self.assertEqual(len(faults), 1, faults)

    def test_a_lying_sonar_is_a_range_fault_of_the_node_naming_the_field(self):
        """The sonar reads -1 m from its 20th message on (a cable come loose) while running
        normally: `<validity field="range">` makes it a `range` fault of the node, whose reset
        restarts it."""
        d = domain()
        validity = '<validity field="range"><min>0.02</min><max>4.0</max></validity>'
        run = peers.KeelRun(self, d, package(ref="sonar.xml"),
                            sonar_files(sonar_profile([("lie_at", "20")], validity=validity)))
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the lie")
        self.assertEqual(fault["kind"], "range")
        self.assertIn("field 'range'", fault["detail"])
        self.assertIn("-1", fault["detail"])
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "its restart")
        self.assertNotEqual(again["pid"], started["pid"])

    def test_a_lying_node_whose_handling_is_stop_is_ended_and_heard_no_more(self):
        """The same lie with severity stop: the node is ended (a `stopped` record of its pid: it
        would have published on) and its faulty values after the first are not taken: one fault."""
        d = domain()
        validity = '<validity field="range"><min>0.02</min><max>4.0</max></validity>'
        run = peers.KeelRun(self, d, package(ref="sonar.xml", policy="<severity>stop</severity>"),
                            sonar_files(sonar_profile([("lie_at", "20")], validity=validity)))
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "stopped" and r["pid"] == started["pid"],
                     30, "the liar stopped")
        time.sleep(0.5)
        faults = records_of(run, event="detected", component="talker")
        self.assertEqual([f["kind"] for f in faults], ["range"], faults)

    def test_a_node_reporting_error_on_diagnostics_is_one_reported_fault_per_episode(self):
        """The sonar's own status on /diagnostics goes to ERROR from its 20th message on (it
        repeats it with every message): one `reported` fault, not one per message; and the same
        status from another process (an impostor) is not the node's."""
        d = domain()
        run = peers.KeelRun(self, d, package(ref="sonar.xml", policy="<severity>ignore</severity>"),
                            sonar_files(sonar_profile([("error_at", "20")], diagnostics=True)))
        self.assertEqual(records_of(run, event="warning"), [])
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the reported error")
        self.assertEqual(fault["kind"], "reported")
        self.assertEqual(fault["detail"], "node '/demo/sonar' reported ERROR: sonar: driver: no echo")
        time.sleep(1.0)  # twenty more ERROR statuses
        self.assertEqual(len(records_of(run, event="detected", component="talker")), 1)

    def test_an_impostors_error_status_is_not_the_nodes(self):
        d = domain()
        run = peers.KeelRun(self, d, package(ref="sonar.xml", policy="<severity>ignore</severity>"),
                            sonar_files(sonar_profile(diagnostics=True)))
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the node up")
        peer = peers.Ros2Peer(self, d)
        pub = peer.node.create_publisher(DiagnosticArray, "/diagnostics", 10)
        for _ in range(40):
            pub.publish(DiagnosticArray(status=[DiagnosticStatus(level=DiagnosticStatus.ERROR, name="sonar: driver",
                                                                 message="impostor")]))
            peer.executor.spin_once(timeout_sec=0.025)
        time.sleep(0.5)
        self.assertEqual(records_of(run, event="detected", component="talker"), [])



class Alternative(unittest.TestCase):
    """`<alternative>` of a node: another node profile takes the role (its name, topics and
    stand-in) when the policy calls for a replacement."""

    def test_a_killed_node_is_replaced_by_its_alternative_whose_values_reach_keel(self):
        """kill -9 of the talker, severity stop with an alternative: the backup talker (the same
        script, the same ROS 2 name and topic, its own greeting) is started in its place, a
        `node` record `replaced` with its own pid; the keel component listening to the role's
        topic hears the backup from then on, and never the old node again."""
        d = domain()
        rec = Path(tempfile.mkdtemp(prefix="keel_rec_")) / "heard.txt"
        app = talker_and_recorder(rec, '<severity>stop</severity><alternative reference="backup.xml"/>')
        backup = node_profile("TalkerBackup", "python3 talker.py", "/demo/talker", [("greeting", "backup")],
                              string_port("chatter", "/demo/chatter"))
        files = {"talker.xml": TALKER, "backup.xml": backup, "talker.py": (HERE / "nodes" / "talker.py").read_text(),
                 "Recorder.xml": RECORDER}
        run = peers.KeelRun(self, d, app, files)
        self.assertEqual(records_of(run, event="warning"), [])
        [up] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up", 30, "the talker up")
        self.assertTrue(wait_until(lambda: rec.exists() and rec.read_text().count(" hi ") >= 3, 30),
                        "the talker's values did not reach the component")
        os.kill(up["pid"], signal.SIGKILL)
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 10,
                               "the talker's death")
        self.assertEqual(fault["kind"], "process")
        [replace] = run.wait_for(lambda r: r.get("event") == "action" and r.get("component") == "talker", 20,
                                 "the handling")
        self.assertEqual(replace["action"], "replace", replace)
        [replaced] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "replaced", 20,
                                  "the alternative's start")
        self.assertNotEqual(replaced["pid"], up["pid"])
        self.assertTrue(wait_until(lambda: rec.read_text().count(" backup ") >= 3, 30),
                        "the alternative's values did not reach the component: " + rec.read_text()[-300:])
        words = [line.split(" ")[1] for line in rec.read_text().splitlines()]
        first = words.index("backup")
        self.assertEqual([w for w in words[first:] if w != "backup"], [], "the old node heard after the new one")
        self.assertTrue(gone(up["pid"]))

    def liar_with_backup(self, max_m, preload):
        """keel run of the sonar lying (-1 m) from its 20th reading, severity stop, its
        alternative the backup sonar reading 2.5 m; both profiles allow [0.02, max_m]."""
        validity = f'<validity field="range"><min>0.02</min><max>{max_m}</max></validity>'
        files = sonar_files(sonar_profile([("lie_at", "20")], validity=validity))
        files["backup.xml"] = sonar_profile([("distance", "2.5")], validity=validity).replace("<name>Sonar<",
                                                                                            "<name>SonarBackup<")
        alternative = f'<alternative reference="backup.xml" preload="{str(preload).lower()}"/>'
        return peers.KeelRun(self, domain(), package(ref="sonar.xml", policy="<severity>stop</severity>" + alternative),
                             files)

    def test_a_live_node_faulty_by_its_values_is_stopped_before_its_alternative_starts(self):
        """The sonar lies (-1 m) while running: its `range` fault, severity stop, replaces it by
        the backup sonar (another distance): keel ends the liar first (never two writers of the
        role's topic), then starts the backup, whose values are in range: no further fault. The
        backup is preloaded: its stand-in is made at start, its process only at the fault."""
        run = self.liar_with_backup(max_m=4.0, preload=True)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker", 30,
                               "the lie")
        self.assertEqual(fault["kind"], "range")
        self.assertEqual(len(records_of(run, event="node", phase="started")), 1, "a second node before the fault")
        [replaced] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "replaced", 20,
                                  "the alternative's start")
        self.assertNotEqual(replaced["pid"], started["pid"])
        self.assertTrue(gone(started["pid"]), "the liar outlived its replacement's start")
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "up" and r["pid"] == replaced["pid"], 30,
                     "the alternative up")
        time.sleep(1.5)  # thirty of its readings
        faults = records_of(run, event="detected", component="talker")
        self.assertEqual([f["kind"] for f in faults], ["range"], faults)

    def test_the_alternatives_values_are_checked_by_its_own_profile_and_a_second_fault_stops_it(self):
        """The backup sonar's profile allows at most 2 m, and it reads 2.5: its values, checked
        by its own port, are a second `range` fault of the role; a role is replaced once, so its
        handling escalates to a fault stop, which ends the backup."""
        run = self.liar_with_backup(max_m=2.0, preload=False)
        [replaced] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "replaced", 30,
                                  "the alternative's start")
        faults = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "talker"
                              and "2.5" in r.get("detail", ""), 30, "the alternative's own range fault")
        self.assertEqual(faults[0]["kind"], "range")
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "stopped" and r["pid"] == replaced["pid"],
                     20, "the alternative stopped")



class Vote(unittest.TestCase):
    @staticmethod
    def voted_sonars(field="range", backup=None):
        """Three sonar nodes, each in a namespace of its own (where it publishes its relative
        `range`); the third lies (2.5 m) from its 40th reading; each one's `field` goes to the
        stock median voter (tolerance 0.2 m), whose sources are the three. With `backup` (metres)
        the third's policy is stop, its alternative a sonar node that reads that from its 40th
        reading on."""
        validity = '<validity field="range"><min>0.02</min><max>4.0</max></validity>'
        files = {"sonar.py": (HERE / "nodes" / "sonar.py").read_text()}
        subs, connections = "", ""
        for i in (1, 2, 3):
            params = [("lie_at", "40"), ("lie", "2.5")] if i == 3 else []
            profile = sonar_profile(params, validity=validity).replace("/demo/", f"/s{i}/")
            files[f"sonar{i}.xml"] = profile.replace("<name>Sonar<", f"<name>Sonar{i}<")
            policy = "<severity>reset</severity>"
            if i == 3 and backup is not None:
                files["backup.xml"] = (sonar_profile([("lie_at", "40"), ("lie", str(backup))], validity=validity)
                                       .replace("/demo/", "/s3/").replace("<name>Sonar<", "<name>SonarBackup<"))
                policy = '<severity>stop</severity><alternative reference="backup.xml"/>'
            subs += (f"<subcomponent><name>sonar{i}</name><reference>sonar{i}.xml</reference>"
                     f"<fault_policy>{policy}</fault_policy></subcomponent>")
            connections += ('<port_connection port_type="data">\n'
                            f'<source component_name="sonar{i}" port_name="range" field="{field}"/>'
                            f'<target component_name="voter" port_name="in{i - 1}"/></port_connection>')
        voter = ROOT / "components" / "voters" / "MedianVoter.xml"
        app = ('<?xml version="1.0"?>\n<package_profile><name>nodes_test</name><subcomponents>' + subs +
               f"<subcomponent><name>voter</name><reference>{voter}</reference><properties>"
               '<property name="tolerance">0.2</property><property name="sources">sonar1 sonar2 sonar3</property>'
               "</properties></subcomponent></subcomponents><port_connections>" + connections +
               "</port_connections></package_profile>\n")
        return app, files

    def test_the_alternative_of_a_voted_node_is_voted_in_its_place(self):
        """The third sonar's vote fault replaces it by its alternative, which agrees with the
        others for two seconds (the voter's episode ends) and then reads 3 m: the field of the
        alternative's messages reaches the voter as the replaced node's did, so it is accused
        in turn, and a role replaced once is then stopped."""
        app, files = self.voted_sonars(backup=3.0)
        run = peers.KeelRun(self, domain(), app, files)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "replaced", 30, "the replacement")
        faults = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "vote"
                              and r.get("fault_id", 0) > 1 and "3" in r.get("detail", ""), 30,
                              "the alternative's vote fault")
        self.assertEqual(faults[0]["component"], "sonar3", faults)
        run.wait_for(lambda r: r.get("event") == "action" and r.get("action") == "stop", 20, "the role stopped")

    def test_a_field_the_message_does_not_have_is_an_error_at_its_line_and_no_node_is_left(self):
        app, files = self.voted_sonars(field="rnge")
        d = Path(tempfile.mkdtemp(prefix="keel_field_"))
        for name, text in {**files, "app.xml": app}.items():
            (d / name).write_text(text)
        ran = subprocess.run([peers.KEEL, "run", str(d / "app.xml"), "--duration", "5", "--log", str(d / "log.jsonl")],
                             env=peers.peer_env(domain()), capture_output=True, text=True, timeout=60)
        self.assertNotEqual(ran.returncode, 0)
        self.assertIn(f"{d / 'app.xml'}:2: port_connection sonar1.range field 'rnge' -> voter.in0: sensor_msgs/msg/Range "
                      "has no field 'rnge'", ran.stderr)
        # keel starts the nodes first, to overlap their start-up with its own: each is stopped.
        records = [json.loads(line) for line in (d / "log.jsonl").read_text().splitlines() if line.strip()]
        started = {r["pid"] for r in records if r.get("event") == "node" and r.get("phase") == "started"}
        stopped = {r["pid"] for r in records if r.get("event") == "node" and r.get("phase") == "stopped"}
        self.assertEqual(started, stopped)
        self.assertTrue(all(gone(pid) for pid in started))

    def test_a_voter_over_three_sonar_nodes_accuses_the_one_that_disagrees_and_it_is_restarted(self):
        """Three sonar nodes read the same wall (1 m); from its 40th reading the third reads 2.5 m,
        in its range but not what the others say. Each one's `range` field goes to the stock
        median voter (a connection carrying a field: <source field="range">): the outlier is a
        `vote` fault of the third node, named by the voter's `sources`; its policy restarts it.
        The other two are never accused."""
        app, files = self.voted_sonars()
        run = peers.KeelRun(self, domain(), app, files)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("component") == "sonar3"
                                 and r.get("phase") == "started", 20, "the third sonar's start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "vote", 30, "the vote fault")
        self.assertEqual((fault["component"], fault["detector"]), ("sonar3", "voter"), fault)
        self.assertIn("2.5", fault["detail"])
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("component") == "sonar3"
                               and r.get("phase") == "restarted", 20, "its restart")
        self.assertNotEqual(again["pid"], started["pid"])
        accused = {r["component"] for r in records_of(run, event="detected")}
        self.assertEqual(accused, {"sonar3"}, records_of(run, event="detected"))



class Model(unittest.TestCase):
    def test_the_stock_monitor_compares_a_nodes_field_with_a_reference_and_accuses_the_node(self):
        """The stock sliding-window monitor (mode absolute, 0.5 m) takes the range of one sonar
        node as its target and of another as its reference (connections carrying the `range`
        field); from its 40th reading the target sonar reads 2.5 m, the reference 1 m: a `model`
        fault of the target node (the monitor's `monitored`), which its policy restarts."""
        files = {"sonar.py": (HERE / "nodes" / "sonar.py").read_text()}
        subs, connections = "", ""
        for name, port, params in (("measured", "target", [("lie_at", "40"), ("lie", "2.5")]),
                                   ("reference", "reference", [])):
            files[f"{name}.xml"] = (sonar_profile(params).replace("/demo/", f"/{name}/")
                                    .replace("<name>Sonar<", f"<name>Sonar_{name}<"))
            subs += (f"<subcomponent><name>{name}</name><reference>{name}.xml</reference>"
                     "<fault_policy><severity>reset</severity></fault_policy></subcomponent>")
            connections += (f'<port_connection port_type="data"><source component_name="{name}" port_name="range" '
                            f'field="range"/><target component_name="monitor" port_name="{port}"/></port_connection>')
        monitor = ROOT / "components" / "monitors" / "SlidingWindowMonitor.xml"
        props = {"window": 3, "threshold": 0.5, "mode": "absolute", "min_consecutive": 2, "min_reference": 0,
                 "monitored": "measured"}
        app = ('<?xml version="1.0"?>\n<package_profile><name>nodes_test</name><subcomponents>' + subs +
               f"<subcomponent><name>monitor</name><reference>{monitor}</reference><properties>" +
               "".join(f'<property name="{k}">{v}</property>' for k, v in props.items()) +
               "</properties></subcomponent></subcomponents><port_connections>" + connections +
               "</port_connections></package_profile>\n")
        run = peers.KeelRun(self, domain(), app, files)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("component") == "measured"
                                 and r.get("phase") == "started", 20, "the measured sonar's start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "model", 30,
                               "the model fault")
        self.assertEqual((fault["component"], fault["detector"]), ("measured", "monitor"), fault)
        again = run.wait_for(lambda r: r.get("event") == "node" and r.get("component") == "measured"
                             and r.get("phase") == "restarted", 20, "its restart")
        self.assertNotEqual(again[0]["pid"], started["pid"])
        self.assertEqual({r["component"] for r in records_of(run, event="detected")}, {"measured"})


if __name__ == "__main__":
    peers.KEEL, peers.COMPONENTS = sys.argv[1], sys.argv[2]  # keel, tests/dds/components.cpp's library
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = str(HERE / "fastdds-lo.xml")
    unittest.main(argv=[sys.argv[0]] + sys.argv[3:], verbosity=2)
