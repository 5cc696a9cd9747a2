#!/usr/bin/env python3
"""keel's DDS ports against a real ROS 2 client: rclpy from PyPI (ROS 2 Kilted, Fast DDS), an
implementation independent of CycloneDDS, which keel uses (docs/dds.md).

  ros2_peer_test.py KEEL_CLI COMPONENT_DIR [unittest options]

Each test runs `keel run` of a package written here (components of tests/dds/components.cpp)
beside an rclpy node, both on a random ROS_DOMAIN_ID so that parallel tests do not hear each
other, both pinned to the loopback (tests/dds/*-lo.xml). Run with the test peers' venv
(scripts/peers.sh)."""
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from domains import domain  # noqa: E402

HERE = Path(__file__).resolve().parent
KEEL = COMPONENTS = None

import rclpy  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import (QoSProfile, qos_profile_sensor_data, DurabilityPolicy, LivelinessPolicy,  # noqa: E402
                       ReliabilityPolicy)
from rclpy.duration import Duration  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue  # noqa: E402
from geometry_msgs.msg import PoseStamped, Twist  # noqa: E402
from sensor_msgs.msg import Imu, JointState, LaserScan, Range  # noqa: E402
from std_msgs.msg import String  # noqa: E402


def peer_env(domain):
    env = dict(os.environ)
    env.update(ROS_DOMAIN_ID=str(domain), CYCLONEDDS_URI=(HERE / "cyclonedds-lo.xml").as_uri(),
               FASTDDS_DEFAULT_PROFILES_FILE=str(HERE / "fastdds-lo.xml"), KEEL_COMPONENT_PATH=COMPONENTS)
    env.pop("ROS_LOCALHOST_ONLY", None)
    env.pop("ROS_AUTOMATIC_DISCOVERY_RANGE", None)
    return env


def component_profile(name, ports, periodic_ms=None, properties=""):
    """A component profile of tests/dds/components.cpp: ports are (name, usage, data_type);
    `properties` its <property> elements."""
    semantics = (f"<type>periodic</type><period>{periodic_ms}</period>" if periodic_ms else "<type>aperiodic</type>")
    port_xml = "".join(f"<data_port><name>{n}</name><usage>{u}</usage><data_type>{t}</data_type>"
                       f"<queue_size>100</queue_size></data_port>" for n, u, t in ports)
    return (f'<?xml version="1.0"?>\n<component_profile><name>{name}</name>'
            f"<execution_environment><library_type>so</library_type><library_name>keel_test_dds_components"
            f"</library_name></execution_environment><execution_semantics>{semantics}</execution_semantics>"
            f"<properties>{properties}</properties><ports>{port_xml}</ports></component_profile>\n")


def echo_profile(cls, ros_type):
    return component_profile(cls, [("in", "input", ros_type), ("out", "output", ros_type)])


class KeelRun:
    """keel run of `package` (XML text) with `components` ({file: XML}) in a temporary directory."""

    def __init__(self, test, domain, package, components, duration=60, args=()):
        self.dir = Path(tempfile.mkdtemp(prefix="keel_dds_"))
        for name, text in components.items():
            (self.dir / name).write_text(text)
        (self.dir / "app.xml").write_text(package)
        self.log = self.dir / "log.jsonl"
        self.proc = subprocess.Popen([KEEL, "run", str(self.dir / "app.xml"), "--duration", str(duration), "--log",
                                      str(self.log), *args], env=peer_env(domain), stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True)
        test.addCleanup(self.stop)
        self.wait_for(lambda r: r.get("event") == "engine" and r.get("phase") == "started", 20, "keel run to start")

    def records(self):
        if not self.log.exists():
            return []
        out = []
        for line in self.log.read_text().splitlines():
            try:
                out.append(json.loads(line))
            except json.JSONDecodeError:
                pass  # a line being written
        return out

    def wait_for(self, pred, seconds, what):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            found = [r for r in self.records() if pred(r)]
            if found:
                return found
            if self.proc.poll() is not None:
                raise AssertionError(f"keel run ended ({self.proc.returncode}) waiting for {what}:\n"
                                     f"{self.proc.stdout.read()}")
            time.sleep(0.05)
        raise AssertionError(f"no {what} within {seconds} s; log:\n" + "\n".join(map(json.dumps, self.records())))

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self.proc.stdout and not self.proc.stdout.closed:  # stop() may be called twice
            self.output = self.proc.stdout.read()
            self.proc.stdout.close()


class Ros2Peer:
    """An rclpy node on `domain`, spun from the test's thread."""

    def __init__(self, test, domain):
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = rclpy.create_node("keel_test_peer", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        test.addCleanup(self.close)

    def spin_until(self, pred, seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if pred():
                return True
            self.executor.spin_once(timeout_sec=0.02)
        return pred()

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


def package(subcomponents, dds, dds_domain=None):
    subs = "".join(f"<subcomponent><name>{n}</name><reference>{ref}</reference>{extra}</subcomponent>"
                   for n, ref, extra in subcomponents)
    dom = f' domain="{dds_domain}"' if dds_domain is not None else ""
    return (f'<?xml version="1.0"?>\n<package_profile><name>dds_test</name><subcomponents>{subs}</subcomponents>'
            f"<dds{dom}>{dds}</dds></package_profile>\n")


def difference(m, candidates):
    """The first field in which `m` differs from the candidate that differs least, as text."""
    def diffs(a, b, path=""):
        out = []
        if hasattr(a, "get_fields_and_field_types"):
            for f in a.get_fields_and_field_types():
                out += diffs(getattr(a, f), getattr(b, f), f"{path}.{f}")
        elif isinstance(a, (list, tuple)) or hasattr(a, "tolist"):
            a, b = list(a), list(b)
            if len(a) != len(b):
                return [f"{path}: {len(a)} elements, sent {len(b)}"]
            for k, (x, y) in enumerate(zip(a, b)):
                out += diffs(x, y, f"{path}[{k}]")
        elif a != b:
            out.append(f"{path}: {a!r}, sent {b!r}")
        return out
    best = min((diffs(m, c) for c in candidates), key=len)
    return f"{len(best)} fields differ, the first: {best[:3]}"


def twist(i):
    t = Twist()
    t.linear.x, t.linear.y, t.linear.z = 0.1 * i, -2.5, 1e-9
    t.angular.z = -0.25 * i
    return t


def laser_scan(i):
    s = LaserScan()
    s.header.frame_id = "laser"
    s.header.stamp.sec, s.header.stamp.nanosec = 1000 + i, 999_999_999
    # float32 fields: values float32 holds exactly (rclpy keeps what it was given; the wire rounds)
    s.angle_min, s.angle_max, s.angle_increment = -1.5, 1.5, 0.00390625
    s.range_min, s.range_max = 0.125, 30.0
    s.ranges = [0.5 + 0.001 * k + i for k in range(1000)]
    s.intensities = [float(k % 7) for k in range(1000)]
    return s


def joint_state(i):
    j = JointState()
    j.header.frame_id = "base"
    j.name = ["left_wheel", "right_wheel", "caster_é"]
    j.position = [0.1 * i, -0.2, 3.0]
    j.velocity = [1.0, 2.0, 3.0]
    j.effort = []
    return j


def pose_stamped(i):
    p = PoseStamped()
    p.header.frame_id = "map"
    p.pose.position.x, p.pose.position.y = float(i), 2.0
    p.pose.orientation.z, p.pose.orientation.w = 0.7071, 0.7071
    return p


def imu(i):
    m = Imu()
    m.header.frame_id = "imu"
    m.orientation.w = 1.0
    m.orientation_covariance = [float(k) for k in range(9)]
    m.angular_velocity.z = 0.5 * i
    m.linear_acceleration.z = 9.81
    m.linear_acceleration_covariance = [-1.0] + [0.0] * 8
    return m


def diagnostic_array(i):
    a = DiagnosticArray()
    a.header.frame_id = "robot"
    for k in range(3):
        s = DiagnosticStatus(level=bytes([k]), name=f"part{k}", message=f"message {i}", hardware_id=f"hw{k}")
        s.values = [KeyValue(key="temperature", value=str(40 + k)), KeyValue(key="state", value="ok")]
        a.status.append(s)
    return a


def string(i):
    return String(data=f"héllo {i} " + "x" * i)


ECHOES = [  # component class, ROS 2 type, message class, a message
    ("EchoTwist", "geometry_msgs/msg/Twist", Twist, twist),
    ("EchoPoseStamped", "geometry_msgs/msg/PoseStamped", PoseStamped, pose_stamped),
    ("EchoString", "std_msgs/msg/String", String, string),
    ("EchoLaserScan", "sensor_msgs/msg/LaserScan", LaserScan, laser_scan),
    ("EchoJointState", "sensor_msgs/msg/JointState", JointState, joint_state),
    ("EchoImu", "sensor_msgs/msg/Imu", Imu, imu),
    ("EchoDiagnosticArray", "diagnostic_msgs/msg/DiagnosticArray", DiagnosticArray, diagnostic_array),
]


class Ros2Interop(unittest.TestCase):
    def test_rclpy_messages_come_back_from_keel_equal_for_every_type(self):
        """rclpy → keel (subscribe) → keel component → keel (publish) → rclpy, for seven types:
        what comes back equals what was sent, field by field (rclpy's message ==)."""
        d = domain()
        components, subs, dds = {}, [], ""
        for cls, ros_type, _, _ in ECHOES:
            components[f"{cls}.xml"] = echo_profile(cls, ros_type)
            inst = cls.lower()
            subs.append((inst, f"{cls}.xml", ""))
            dds += (f'<subscribe component="{inst}" port="in" topic="/keel_in/{inst}" type="{ros_type}"/>'
                    f'<publish component="{inst}" port="out" topic="keel_out/{inst}" type="{ros_type}"/>')
        # The profile says domain 0; ROS_DOMAIN_ID (d, never 0) overrides it, or nothing comes back.
        run = KeelRun(self, d, package(subs, dds, dds_domain=0), components)
        peer = Ros2Peer(self, d)
        got = {cls: [] for cls, *_ in ECHOES}
        pubs = {}
        for cls, _, msg_type, _ in ECHOES:
            inst = cls.lower()
            pubs[cls] = peer.node.create_publisher(msg_type, f"/keel_in/{inst}", 10)
            peer.node.create_subscription(msg_type, f"/keel_out/{inst}", lambda m, c=cls: got[c].append(m), 10)
        # Until every round trip works (discovery takes up to a second or so), then 5 more each.
        sent = {cls: [] for cls, *_ in ECHOES}
        deadline = time.monotonic() + 30
        i = 0
        while time.monotonic() < deadline and not all(len(got[c]) >= 5 for c in got):
            for cls, _, _, make in ECHOES:
                m = make(i)
                sent[cls].append(m)
                pubs[cls].publish(m)
            i += 1
            peer.spin_until(lambda: False, 0.1)
        for cls, *_ in ECHOES:
            self.assertGreaterEqual(len(got[cls]), 5, f"{cls}: {len(got[cls])} came back; keel said:\n"
                                    + "\n".join(map(json.dumps, run.records()[-20:])))
            for m in got[cls]:
                if m not in sent[cls]:
                    self.fail(f"{cls}: a message came back that rclpy did not send; against the nearest sent: "
                              f"{difference(m, sent[cls])}")
        # The domain given by the profile (0, or 1) is overridden by ROS_DOMAIN_ID: we heard it.

    def test_keel_topics_are_seen_by_ros2_with_their_names_types_and_qos(self):
        """A keel publication and subscription, as ROS 2's graph reports them; and keel's
        sensor_data ranges arrive at an rclpy sensor_data subscription, in order."""
        d = domain()
        components = {"RangeSource.xml": component_profile("RangeSource", [("range", "output",
                                                                             "sensor_msgs/msg/Range")], 20),
                      "EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<publish component="sonar" port="range" topic="/sonar/range" type="sensor_msgs/msg/Range" '
               'qos="sensor_data"/>'
               '<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist" '
               'qos="reliable"/>')
        KeelRun(self, d, package([("sonar", "RangeSource.xml", ""), ("planner", "EchoTwist.xml", "")], dds),
                components)
        peer = Ros2Peer(self, d)
        ranges = []
        peer.node.create_subscription(Range, "/sonar/range", ranges.append, qos_profile_sensor_data)

        def names():
            return dict(peer.node.get_topic_names_and_types())
        self.assertTrue(peer.spin_until(lambda: "/sonar/range" in names() and "/cmd_vel" in names() and
                                        len(ranges) >= 10, 20), f"graph: {names()}, ranges: {len(ranges)}")
        self.assertEqual(names()["/sonar/range"], ["sensor_msgs/msg/Range"])
        self.assertEqual(names()["/cmd_vel"], ["geometry_msgs/msg/Twist"])
        [pub] = peer.node.get_publishers_info_by_topic("/sonar/range")
        self.assertEqual(pub.topic_type, "sensor_msgs/msg/Range")
        self.assertEqual(pub.qos_profile.reliability, ReliabilityPolicy.BEST_EFFORT)
        [sub] = peer.node.get_subscriptions_info_by_topic("/cmd_vel")
        self.assertEqual(sub.qos_profile.reliability, ReliabilityPolicy.RELIABLE)
        self.assertEqual(sub.qos_profile.durability, DurabilityPolicy.VOLATILE)
        r = ranges[-1]
        self.assertEqual(r.header.frame_id, "sonar_front")
        self.assertEqual(r.radiation_type, Range.ULTRASOUND)
        self.assertAlmostEqual(r.field_of_view, 0.5, places=6)
        self.assertAlmostEqual(r.max_range, 4.0, places=6)
        steps = [b.header.stamp.sec - a.header.stamp.sec for a, b in zip(ranges, ranges[1:])]
        self.assertTrue(all(s >= 1 for s in steps), f"ranges out of order: {steps}")
        for m in ranges:
            self.assertAlmostEqual(m.range, 0.5 + 0.01 * m.header.stamp.sec, places=4)


class Graph(unittest.TestCase):
    def test_keel_run_is_a_node_of_the_ros2_graph_with_its_topics_and_leaves_it_when_it_ends(self):
        """rclpy's graph (what `ros2 node list` and `ros2 node info` read) shows keel's run as
        /keel/<its name made a node name>, with its publications and subscriptions, and no more
        once keel run has ended."""
        d = domain()
        components = {"RangeSource.xml": component_profile("RangeSource", [("range", "output",
                                                                             "sensor_msgs/msg/Range")], 20),
                      "EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<publish component="sonar" port="range" topic="/sonar/range" type="sensor_msgs/msg/Range" '
               'qos="sensor_data"/>'
               '<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist"/>')
        app = package([("sonar", "RangeSource.xml", ""), ("planner", "EchoTwist.xml", "")], dds)
        app = app.replace("<name>dds_test</name>", "<name>2 robots-test</name>")  # not a node name as it is
        run = KeelRun(self, d, app, components)
        peer = Ros2Peer(self, d)
        name, ns = "keel_2_robots_test", "/keel"

        def nodes():
            return peer.node.get_node_names_and_namespaces()
        self.assertTrue(peer.spin_until(lambda: (name, ns) in nodes(), 20), f"nodes: {nodes()}")

        def publishers():
            return dict(peer.node.get_publisher_names_and_types_by_node(name, ns))

        def subscriptions():
            return dict(peer.node.get_subscriber_names_and_types_by_node(name, ns))
        self.assertTrue(peer.spin_until(lambda: "/sonar/range" in publishers() and "/cmd_vel" in subscriptions(),
                                        20), f"publishers: {publishers()}, subscriptions: {subscriptions()}")
        self.assertEqual(publishers()["/sonar/range"], ["sensor_msgs/msg/Range"])
        self.assertEqual(subscriptions()["/cmd_vel"], ["geometry_msgs/msg/Twist"])
        self.assertIn("/diagnostics", publishers())
        self.assertNotIn("/cmd_vel", publishers())
        run.stop()
        self.assertTrue(peer.spin_until(lambda: (name, ns) not in nodes(), 20),
                        f"keel's run is still in the graph after it ended: {nodes()}")


class Diagnostics(unittest.TestCase):
    def test_diagnostics_say_each_components_health_and_follow_an_injected_fault(self):
        """keel's /diagnostics, read by rclpy: one DiagnosticStatus per component, OK while it
        runs; an injected exception under `severity stop` makes the sonar's ERROR, with its
        state and fault; the planner stays OK."""
        d = domain()
        components = {"RangeSource.xml": component_profile("RangeSource", [("range", "output",
                                                                             "sensor_msgs/msg/Range")], 20),
                      "EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<publish component="sonar" port="range" topic="/sonar/range" type="sensor_msgs/msg/Range"/>'
               '<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist"/>')
        policy = "<fault_policy><severity>stop</severity></fault_policy>"
        scenario = Path(tempfile.mkdtemp(prefix="keel_dds_")) / "throw.xml"
        scenario.write_text('<fault_scenario><fault at="3000" component="sonar" kind="throw"/></fault_scenario>')
        run = KeelRun(self, d, package([("sonar", "RangeSource.xml", policy), ("planner", "EchoTwist.xml", "")], dds),
                      components, args=("--inject", str(scenario)))
        peer = Ros2Peer(self, d)
        arrays = []
        peer.node.create_subscription(DiagnosticArray, "/diagnostics", lambda a: arrays.append((time.monotonic(), a)),
                                      10)

        def status(a, name):
            return next((s for s in a.status if s.name == name), None)

        def levels(name):
            return [status(a, name).level for _, a in arrays if status(a, name)]
        self.assertTrue(peer.spin_until(lambda: len(levels("keel/dds_test/sonar")) >= 2, 10), arrays)
        ok, error = DiagnosticStatus.OK, DiagnosticStatus.ERROR
        first = arrays[0][1]
        self.assertEqual(sorted(s.name for s in first.status), ["keel/dds_test/planner", "keel/dds_test/sonar"])
        sonar = status(first, "keel/dds_test/sonar")
        self.assertEqual(sonar.level, ok, sonar)
        self.assertEqual({v.key: v.value for v in sonar.values}, {"state": "Active", "faults": "0", "last_fault": ""})
        self.assertTrue(peer.spin_until(lambda: error in levels("keel/dds_test/sonar"), 15), levels("keel/dds_test/sonar"))
        [stopped] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("component") == "sonar", 5, "the fault")
        bad = next(a for t, a in arrays if status(a, "keel/dds_test/sonar").level == error)
        values = {v.key: v.value for v in status(bad, "keel/dds_test/sonar").values}
        self.assertEqual(values["faults"], "1")
        self.assertIn("exception", values["last_fault"])
        self.assertEqual(status(bad, "keel/dds_test/planner").level, ok)
        self.assertEqual(stopped["kind"], "exception")
        # That it is said at once, not at the next tick: tests/unit/dds/diagnostics_test.cpp.


class BadInput(unittest.TestCase):
    def run_keel(self, package_xml, components):
        d = Path(tempfile.mkdtemp(prefix="keel_dds_"))
        for name, text in components.items():
            (d / name).write_text(text)
        (d / "app.xml").write_text(package_xml)
        return subprocess.run([KEEL, "run", str(d / "app.xml"), "--duration", "1"], env=peer_env(domain()),
                              capture_output=True, text=True, timeout=60), d / "app.xml"

    def test_a_type_whose_message_code_is_not_linked_is_a_load_error_with_its_line(self):
        """The profile and the code agree (keel_test_msgs/msg/Nothing), but no message code of
        that type is in the process: keel run refuses to start, naming the <subscribe>'s line."""
        ros_type = "keel_test_msgs/msg/Nothing"
        xml = package([("echo", "EchoUnlinked.xml", "")],
                      f'\n\n<subscribe component="echo" port="in" topic="/in" type="{ros_type}"/>\n')
        line = xml[:xml.index("<subscribe")].count("\n") + 1
        ran, app = self.run_keel(xml, {"EchoUnlinked.xml": echo_profile("EchoUnlinked", ros_type)})
        self.assertNotEqual(ran.returncode, 0)
        self.assertIn(f"{app}:{line}: <subscribe> of echo.in: no message type '{ros_type}' is linked into this keel",
                      ran.stderr)

    def test_a_port_whose_code_type_is_not_the_topics_is_a_load_error(self):
        """The profile says sensor_msgs/msg/Range for a port whose code is a Twist: the code's
        port check refuses it before DDS is reached, naming the port and both types."""
        ran, app = self.run_keel(package([("echo", "EchoTwist.xml", "")],
                                         '<subscribe component="echo" port="in" topic="/in" '
                                         'type="sensor_msgs/msg/Range"/>'),
                                 {"EchoTwist.xml": echo_profile("EchoTwist", "sensor_msgs/msg/Range")})
        self.assertNotEqual(ran.returncode, 0)
        self.assertIn("geometry_msgs/msg/Twist", ran.stderr)
        self.assertIn("sensor_msgs/msg/Range", ran.stderr)


class RemoteFaults(unittest.TestCase):
    # Wide enough that no sample gap of a loaded machine (or of keel under TSan) misses it
    # before the kill; the figures for tight ones are keel bench's.
    QOS = dict(deadline=300, liveliness=600)

    def start_publisher(self, d, delay_ms=0):
        return subprocess.Popen([sys.executable, str(HERE / "ros2_publisher.py"), "/cmd_vel", "20",
                                 str(self.QOS["deadline"]), str(self.QOS["liveliness"]), str(delay_ms)],
                                env=peer_env(d), stdout=subprocess.PIPE, text=True)

    def echo_and_kill(self, d):
        """keel run echoing /cmd_vel, with its deadline and lease; an rclpy publisher heard, then
        killed with kill -9: keel run, the peer, the `remote` fault, the kill's time."""
        components = {"EchoTwist.xml": echo_profile("EchoTwist", "geometry_msgs/msg/Twist")}
        dds = ('<subscribe component="planner" port="in" topic="/cmd_vel" type="geometry_msgs/msg/Twist" '
               f'deadline="{self.QOS["deadline"]}" liveliness="{self.QOS["liveliness"]}"/>'
               '<publish component="planner" port="out" topic="/cmd_vel_echo" type="geometry_msgs/msg/Twist"/>')
        run = KeelRun(self, d, package([("planner", "EchoTwist.xml", "")], dds), components)
        peer = Ros2Peer(self, d)
        echoes = []
        peer.node.create_subscription(Twist, "/cmd_vel_echo", echoes.append, 10)
        pub = self.start_publisher(d)
        self.addCleanup(lambda: pub.poll() is None and pub.kill())
        self.assertEqual(pub.stdout.readline().strip(), "publishing")
        # keel hears it: the planner echoes what it takes (discovery can take a second or so)
        self.assertTrue(peer.spin_until(lambda: len(echoes) >= 10, 20), "keel never echoed the publisher")
        # A gap in the first samples longer than the deadline (a loaded machine, keel under TSan)
        # is a real outage: keel says it and, the samples flowing, its recovery. Such an early
        # outage must be over before the kill; the kill's fault is the one after it.
        before = self.outages_over(run)
        killed = time.monotonic()
        pub.send_signal(signal.SIGKILL)
        pub.wait()
        [fault] = run.wait_for(lambda r: r.get("event") == "detected" and r.get("kind") == "remote"
                               and r not in before, 5, "a remote fault")
        return run, peer, fault, killed, before

    def outages_over(self, run):
        """The faults detected so far, once each has its recovery (waited for): none in a run
        whose samples came steadily from the start."""
        def ended():
            records = run.records()
            recovered = {r.get("fault_id") for r in records if r.get("event") == "recovered"}
            detected = [r for r in records if r.get("event") == "detected"]
            return detected if all(f.get("fault_id") in recovered for f in detected) else None
        end = time.monotonic() + 5
        while (detected := ended()) is None:
            self.assertLess(time.monotonic(), end, f"an outage before the kill did not end: {run.records()}")
            time.sleep(0.05)
        for f in detected:  # only what a gap in the samples is: a remote fault of the subscriber
            self.assertEqual((f["kind"], f["component"]), ("remote", "planner"), f)
        return detected

    def test_a_killed_rclpy_publisher_is_a_remote_fault_and_its_return_a_recovery(self):
        """rclpy publishes /cmd_vel at 20 ms offering deadline 300 ms and lease 600 ms; keel
        subscribes requesting them. kill -9 of the publisher: one `remote` fault of the
        subscriber (deadline, then liveliness, are one outage); a new publisher: `recovered`."""
        d = domain()
        run, _, fault, killed, before = self.echo_and_kill(d)
        waited = time.monotonic() - killed
        self.assertEqual(fault["component"], "planner")
        self.assertEqual(fault["detector"], "dds")
        self.assertIn("/cmd_vel", fault["detail"])
        # Generous (a busy 2-core machine): the deadline is 300 ms after the last sample.
        self.assertLess(waited, 3.0)
        time.sleep(1.0)  # liveliness (600 ms) is lost too: the same outage, no second fault
        self.assertEqual(len([r for r in run.records() if r.get("event") == "detected"]), len(before) + 1,
                         run.records())
        again = self.start_publisher(d)
        self.addCleanup(lambda: again.poll() is None and again.kill())
        [rec] = run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"], 20,
                             "the remote fault's recovery")
        self.assertEqual(rec["component"], "planner")

    def test_a_publisher_alive_before_it_writes_ends_the_outage_with_its_first_message(self):
        """After the kill's fault, a new publisher alive for 1.5 s (five deadlines) before its
        first message, as a node still starting: its liveliness alone does not end the outage
        (the deadline firing meanwhile would open a second fault); its first message does."""
        d = domain()
        run, _, fault, _, before = self.echo_and_kill(d)
        again = self.start_publisher(d, delay_ms=1500)
        self.addCleanup(lambda: again.poll() is None and again.kill())
        self.assertEqual(again.stdout.readline().strip(), "alive")
        self.assertEqual(again.stdout.readline().strip(), "publishing")
        [rec] = run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"], 20,
                             "the remote fault's recovery")
        time.sleep(1.0)  # the deadline would have fired meanwhile: nothing more
        detected = [r for r in run.records() if r.get("event") == "detected"]
        self.assertEqual(detected, before + [fault], run.records())
        recoveries = [r for r in run.records() if r.get("event") == "recovered" and r.get("fault_id") not in
                      {f["fault_id"] for f in before}]
        self.assertEqual(recoveries, [rec], run.records())
        # The outage lasted from the fault to the first message, at least the delay's most.
        self.assertGreater(rec["t_ns"] - fault["t_ns"], 1.0e9, rec)


if __name__ == "__main__":
    KEEL, COMPONENTS = sys.argv[1], sys.argv[2]
    # This process's rclpy nodes too: Fast DDS reads its profile when the first node is made.
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = str(HERE / "fastdds-lo.xml")
    unittest.main(argv=[sys.argv[0]] + sys.argv[3:], verbosity=2)
