#!/usr/bin/env python3
"""DDS ports of a component in a `<process>` of its own (docs/dds.md#components-in-a-process,
decision 0019), against rclpy: the endpoints are the component process's, a standby's are made
ahead and stand by, and they carry the topics on through a kill -9 of the active process.

  process_test.py KEEL_CLI COMPONENT_DIR [unittest options]

Run with the test peers' venv (scripts/peers.sh), as ros2_peer_test.py, whose helpers these
tests share."""
import os
import queue
import signal
import subprocess
import sys
import threading
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ros2_peer_test as peer  # noqa: E402
from domains import domain  # noqa: E402
from ros2_peer_test import KeelRun, Ros2Peer, component_profile, echo_profile  # noqa: E402

from geometry_msgs.msg import Twist  # noqa: E402
from rclpy.qos import qos_profile_sensor_data  # noqa: E402
from sensor_msgs.msg import JointState, Range  # noqa: E402

HERE = Path(__file__).resolve().parent
RESET_PROCESS = "<severity kind=\"process\">reset</severity>"


def package(subcomponents, dds, diagnostics=False):
    """A package whose <dds> publishes no /diagnostics unless asked: keel run then joins DDS only
    for the bindings of its own components (here none), so that its sockets tell where the
    endpoints are."""
    subs = "".join(f"<subcomponent><name>{n}</name><reference>{ref}</reference>{extra}</subcomponent>"
                   for n, ref, extra in subcomponents)
    return (f'<?xml version="1.0"?>\n<package_profile><name>dds_test</name><subcomponents>{subs}</subcomponents>'
            f'<dds diagnostics="{str(diagnostics).lower()}">{dds}</dds></package_profile>\n')


def in_process(name, policy=RESET_PROCESS, standby=0):
    return f'<fault_policy>{policy}</fault_policy><process name="{name}" standby="{standby}"/>'


def udp_sockets(pid):
    """The UDP sockets (inodes) process `pid` holds: CycloneDDS's participant is a few of them."""
    udp = set()
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        with open(table) as f:
            udp |= {line.split()[9] for line in list(f)[1:]}
    held = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue  # closed meanwhile
        if target.startswith("socket:[") and target[8:-1] in udp:
            held.add(target[8:-1])
    return held


def hosts(run, phase):
    """The pids of the host records of `phase` (standby, active, took_over, ...), in log order."""
    return [r["pid"] for r in run.records() if r.get("event") == "host" and r.get("phase") == phase]


def seq(i):
    t = Twist()
    t.linear.x = float(i)
    return t


class Process(unittest.TestCase):
    def test_a_component_in_a_process_publishes_from_that_process_and_again_after_a_respawn(self):
        """A RangeSource in <process name="sonar">: rclpy hears its ranges, and the DDS sockets
        are the host's, none keel run's. kill -9 of the host (no standby): keel run respawns it,
        and ranges come again, from the new host's writer."""
        d = domain()
        components = {"RangeSource.xml": component_profile("RangeSource", [("range", "output",
                                                                             "sensor_msgs/msg/Range")], 20)}
        dds = ('<publish component="sonar" port="range" topic="/sonar/range" type="sensor_msgs/msg/Range" '
               'qos="sensor_data"/>')
        run = KeelRun(self, d, package([("sonar", "RangeSource.xml", in_process("sonar"))], dds), components)
        ros = Ros2Peer(self, d)
        ranges = []
        ros.node.create_subscription(Range, "/sonar/range", ranges.append, qos_profile_sensor_data)
        self.assertTrue(ros.spin_until(lambda: len(ranges) >= 10, 20), f"{len(ranges)} ranges; {run.records()}")
        [host] = hosts(run, "active")
        self.assertEqual(udp_sockets(run.proc.pid), set(), "keel run joined DDS for a component of a <process>")
        self.assertNotEqual(udp_sockets(host), set(), "the sonar's host has no DDS socket")
        steps = [b.header.stamp.sec - a.header.stamp.sec for a, b in zip(ranges, ranges[1:])]
        self.assertTrue(all(s >= 1 for s in steps), f"ranges out of order: {steps}")
        [before] = ros.node.get_publishers_info_by_topic("/sonar/range")

        killed = time.monotonic()
        os.kill(host, signal.SIGKILL)
        [respawned] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "respawned", 20,
                                   "the respawn")
        self.assertNotEqual(respawned["pid"], host)
        ros.spin_until(lambda: False, 0.2)  # what rclpy had queued: its depth (5) at most, the dead host's
        heard = len(ranges)
        self.assertTrue(ros.spin_until(lambda: len(ranges) > heard, 20),
                        "no range of the respawned sonar reached rclpy")
        print(f"ranges again {(time.monotonic() - killed) * 1e3:.0f} ms after the kill (respawn and discovery)",
              file=sys.stderr)
        self.assertTrue(ros.spin_until(lambda: len(ranges) >= heard + 10, 20))
        gids = {bytes(p.endpoint_gid) for p in ros.node.get_publishers_info_by_topic("/sonar/range")}
        self.assertIn(True, [g != bytes(before.endpoint_gid) for g in gids], "no new writer in the graph")
        self.assertEqual(udp_sockets(run.proc.pid), set())
        self.assertNotEqual(udp_sockets(respawned["pid"]), set())

    def test_rclpy_messages_come_back_from_components_in_a_process_equal(self):
        """rclpy → keel → an echo in <process name="echoes"> → keel → rclpy, for a Twist and a
        JointState (strings and sequences: no ring between processes could carry it)."""
        d = domain()
        types = [("EchoTwist", "geometry_msgs/msg/Twist", Twist, peer.twist),
                 ("EchoJointState", "sensor_msgs/msg/JointState", JointState, peer.joint_state)]
        components, subs, dds = {}, [], ""
        for cls, ros_type, _, _ in types:
            components[f"{cls}.xml"] = echo_profile(cls, ros_type)
            inst = cls.lower()
            subs.append((inst, f"{cls}.xml", in_process("echoes")))
            dds += (f'<subscribe component="{inst}" port="in" topic="/keel_in/{inst}" type="{ros_type}"/>'
                    f'<publish component="{inst}" port="out" topic="/keel_out/{inst}" type="{ros_type}"/>')
        run = KeelRun(self, d, package(subs, dds), components)
        ros = Ros2Peer(self, d)
        got = {cls: [] for cls, *_ in types}
        sent = {cls: [] for cls, *_ in types}
        pubs = {}
        for cls, _, msg_type, _ in types:
            pubs[cls] = ros.node.create_publisher(msg_type, f"/keel_in/{cls.lower()}", 10)
            ros.node.create_subscription(msg_type, f"/keel_out/{cls.lower()}", lambda m, c=cls: got[c].append(m), 10)
        end, i = time.monotonic() + 30, 0
        while time.monotonic() < end and not all(len(g) >= 5 for g in got.values()):
            for cls, _, _, make in types:
                sent[cls].append(make(i))
                pubs[cls].publish(sent[cls][-1])
            i += 1
            ros.spin_until(lambda: False, 0.1)
        for cls, *_ in types:
            self.assertGreaterEqual(len(got[cls]), 5, f"{cls}: {len(got[cls])} came back; {run.records()[-10:]}")
            for m in got[cls]:
                self.assertIn(m, sent[cls], f"{cls}: {peer.difference(m, sent[cls])}")
        [host] = hosts(run, "active")
        self.assertEqual(udp_sockets(run.proc.pid), set())
        self.assertNotEqual(udp_sockets(host), set())

    def test_a_standby_carries_the_topics_on_when_the_active_is_killed(self):
        """An echo in <process standby="1">: the standby's endpoints are in ROS 2's graph before
        it serves, and it holds no socket of keel run's (which publishes /diagnostics). kill -9
        of the active: the standby takes over (the log says so), the echoes go on at once from
        its writer, and nothing it was sent while standing by is echoed (the active had)."""
        d = domain()
        components = {"EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist"/>'
               '<publish component="planner" port="out" topic="/cmd_vel_echo" type="geometry_msgs/msg/Twist"/>')
        # /diagnostics: keel run joins DDS too, before it starts the standby
        run = KeelRun(self, d, package([("planner", "EchoTwist.xml", in_process("planner", standby=1))], dds,
                                       diagnostics=True), components)
        ros = Ros2Peer(self, d)
        echoes = []  # (when rclpy took it, its number)
        ros.node.create_subscription(Twist, "/cmd_vel_echo", lambda m: echoes.append((time.monotonic(), m.linear.x)),
                                     100)
        pub = ros.node.create_publisher(Twist, "/cmd_vel", 100)
        sent = []  # (when, number)

        def publish_for(seconds):
            end = time.monotonic() + seconds
            while time.monotonic() < end:
                sent.append((time.monotonic(), len(sent)))
                pub.publish(seq(len(sent) - 1))
                ros.spin_until(lambda: False, 0.02)

        [active] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "active", 10, "the active")
        [standby] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "standby", 10,
                                 "the standby")
        self.assertTrue(ros.spin_until(lambda: len(ros.node.get_publishers_info_by_topic("/cmd_vel_echo")) == 2 and
                                       len(ros.node.get_subscriptions_info_by_topic("/cmd_vel")) == 2, 20),
                        "the active's and the standby's endpoints are not both in the graph")
        self.assertNotEqual(udp_sockets(run.proc.pid), set(), "keel run publishes /diagnostics")
        self.assertEqual(udp_sockets(standby["pid"]) & udp_sockets(run.proc.pid), set(),
                         "the standby holds keel run's DDS sockets")
        publish_for(0.5)
        self.assertTrue(ros.spin_until(lambda: len(echoes) >= 10, 20), "no echo before the kill")
        publish_for(2)  # the standby's reader is sent all of these too

        killed = time.monotonic()
        os.kill(active["pid"], signal.SIGKILL)
        publish_for(3)
        ros.spin_until(lambda: False, 0.5)
        [took] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "took_over", 5, "the takeover")
        self.assertEqual(took["pid"], standby["pid"])
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "process", 5, "the fault")
        self.assertEqual((fault["component"], fault["detector"]), ("planner", "supervisor"))
        run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"], 5,
                     "its recovery")
        after = [n for t, n in echoes if t > killed]
        sent_after = {n for t, n in sent if t > killed}
        first = min(t for t, n in echoes if n in sent_after)
        print(f"the first echo of a value sent after the kill: {(first - killed) * 1e3:.1f} ms after it "
              f"(values every 20 ms)", file=sys.stderr)
        self.assertGreater(len(sent_after & set(after)), 0.9 * len(sent_after),
                           f"{len(after)} echoes of the {len(sent_after)} sent after the kill")
        stale = sorted(n for n in after if n < min(sent_after) - 25)  # sent ≥ 0.5 s before the kill
        self.assertEqual(stale, [], "the standby echoed what it was sent while standing by")


class ProcessRemoteFaults(unittest.TestCase):
    QOS = dict(deadline=300, liveliness=600)

    def start_publisher(self, d, readers=2):
        """An rclpy publisher of /cmd_vel (ros2_publisher.py), once `readers` keel readers (the
        active's and the standby's) know its writer: a reader that never matched a writer cannot
        tell that it was lost, and a standby's discovery of a new writer can lag the active's."""
        p = subprocess.Popen([sys.executable, str(HERE / "ros2_publisher.py"), "/cmd_vel", "20",
                              str(self.QOS["deadline"]), str(self.QOS["liveliness"]), "0", str(readers)],
                             env=peer.peer_env(d), stdout=subprocess.PIPE, text=True)
        self.addCleanup(lambda: p.poll() is None and (p.kill(), p.wait()))
        lines = queue.Queue()
        threading.Thread(target=lambda: [lines.put(line.strip()) for line in p.stdout], daemon=True).start()

        def line(what):
            try:
                return lines.get(timeout=20)
            except queue.Empty:
                self.fail(f"the publisher printed no {what} within 20 s")
        self.assertEqual(line("'publishing'"), "publishing")
        self.assertRegex(line(f"'heard by {readers}'"), r"^heard by \d+$")
        return p

    def remote(self, run):
        return [r for r in run.records() if r.get("event") == "detected" and r.get("kind") == "remote"]

    def test_a_lost_writer_is_a_remote_fault_of_the_active_host_alone_before_and_after_takeovers(self):
        """An echo in <process standby="1"> subscribing with deadline and lease, remote faults
        reset. A killed rclpy publisher is one `remote` fault, the active host's (its pid), reset
        by its policy: the standby, which hears the same writer, reports nothing. kill -9 of the
        active while the writer is lost: the standby kept the outage to itself, and reports it
        once it serves. With a new publisher, kill -9 of that active: the next standby takes the
        topic on without a fault, and the next lost writer is its fault.
        Each standby is ready before the publisher it must hear starts: a publisher finds every
        reader as it starts, a reader made later only at its next announcement."""
        d = domain()
        components = {"EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist" '
               f'deadline="{self.QOS["deadline"]}" liveliness="{self.QOS["liveliness"]}"/>'
               '<publish component="planner" port="out" topic="/cmd_vel_echo" type="geometry_msgs/msg/Twist"/>')
        policy = RESET_PROCESS + '<severity kind="remote">reset</severity>'
        run = KeelRun(self, d, package([("planner", "EchoTwist.xml", in_process("planner", policy, standby=1))],
                                       dds), components)
        ros = Ros2Peer(self, d)
        echoes = []
        ros.node.create_subscription(Twist, "/cmd_vel_echo", echoes.append, 10)

        def echoed(what):
            heard = len(echoes)
            self.assertTrue(ros.spin_until(lambda: len(echoes) >= heard + 10, 20), f"no echo {what}")
            ros.spin_until(lambda: False, 1)  # a new rclpy publisher's first samples may leave a gap

        def standby_besides(active):
            run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "standby" and r["pid"] != active and
                         r["pid"] not in hosts(run, "took_over"), 10, "a standby")

        def take_over(active, n):
            """kill -9 of the active host: the n-th takeover; the new active's pid."""
            os.kill(active, signal.SIGKILL)
            run.wait_for(lambda r: len(hosts(run, "took_over")) >= n, 10, f"takeover {n}")
            return hosts(run, "took_over")[-1]

        def remote_fault_of(host, n):
            """The n-th remote fault, of `host`, reset by it; no other, the lease lost too."""
            run.wait_for(lambda r: len(self.remote(run)) >= n, 5, f"remote fault {n}")
            time.sleep(1.5)  # the lease (600 ms) is lost too: the same outage; a standby would have said so
            faults = self.remote(run)
            self.assertEqual(len(faults), n, "\n".join(map(str, run.records())))
            fault = faults[-1]
            self.assertEqual((fault["component"], fault["detector"], fault["pid"]), ("planner", "dds", host))
            self.assertIn("/cmd_vel", fault["detail"])
            [reset] = run.wait_for(lambda r: r.get("event") == "action" and r.get("fault_id") == fault["fault_id"], 5,
                                   "the remote fault's reset")
            self.assertEqual((reset["action"], reset["pid"]), ("reset", host))

        [first] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "active", 10, "the active")
        first = first["pid"]
        standby_besides(first)
        publisher = self.start_publisher(d)
        echoed("of the first publisher")
        n = len(self.remote(run))  # none, unless the new publisher's first samples left a gap
        publisher.send_signal(signal.SIGKILL)
        publisher.wait()
        remote_fault_of(first, n + 1)

        second = take_over(first, 1)
        remote_fault_of(second, n + 2)

        standby_besides(second)
        publisher = self.start_publisher(d)
        echoed("of the second publisher, by the new active")
        third = take_over(second, 2)
        echoed("after the second takeover")
        self.assertEqual([f for f in self.remote(run) if f["pid"] == third], [], "the takeover lost the writer")
        n = len(self.remote(run))
        publisher.send_signal(signal.SIGKILL)
        publisher.wait()
        remote_fault_of(third, n + 1)

    def test_a_writer_lost_while_a_standby_stood_by_is_its_fault_when_it_takes_over(self):
        """A lease alone (no deadline, whose listener would fire again after the takeover): the
        lost writer's liveliness is told once, to the active and to the standby alike. The active
        reports it; kill -9 of the active: the standby reports the outage it kept, which lasts.
        The writer is killed only once both readers know it (start_publisher): a standby that
        never matched a writer has no outage to keep (docs/dds.md)."""
        d = domain()
        components = {"EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist" '
               f'liveliness="{self.QOS["liveliness"]}"/>'
               '<publish component="planner" port="out" topic="/cmd_vel_echo" type="geometry_msgs/msg/Twist"/>')
        run = KeelRun(self, d, package([("planner", "EchoTwist.xml", in_process("planner", standby=1))], dds),
                      components)
        ros = Ros2Peer(self, d)
        echoes = []
        ros.node.create_subscription(Twist, "/cmd_vel_echo", echoes.append, 10)
        [active] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "active", 10, "the active")
        [standby] = run.wait_for(lambda r: r.get("event") == "host" and r.get("phase") == "standby", 10, "the standby")
        publisher = self.start_publisher(d)
        self.assertTrue(ros.spin_until(lambda: len(echoes) >= 10, 20), "keel never echoed the publisher")
        publisher.send_signal(signal.SIGKILL)
        publisher.wait()
        [lost] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "remote", 5, "the fault")
        time.sleep(1)
        self.assertEqual(len(self.remote(run)), 1, self.remote(run))
        self.assertEqual(lost["pid"], active["pid"])
        self.assertIn("lost its liveliness", lost["detail"])

        os.kill(active["pid"], signal.SIGKILL)
        [held] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "remote" and
                              r.get("pid") == standby["pid"], 5, "the outage, reported by the new active")
        self.assertIn("lost its liveliness", held["detail"])
        self.assertEqual(len(self.remote(run)), 2, self.remote(run))


if __name__ == "__main__":
    peer.KEEL, peer.COMPONENTS = sys.argv[1], sys.argv[2]
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = str(HERE / "fastdds-lo.xml")
    unittest.main(argv=[sys.argv[0]] + sys.argv[3:], verbosity=2)
