#!/usr/bin/env python3
"""Managed (lifecycle) ROS 2 nodes under keel, against a real rclpy.lifecycle node (ROS 2 Kilted
from PyPI, Fast DDS): tests/dds/nodes/lifecycle_talker.py, which knows nothing of keel, driven by
`keel run` through its `~/change_state` service and confirmed by its `~/transition_event`
(docs/ros2-nodes.md#lifecycle-nodes).

  lifecycle_test.py KEEL_CLI COMPONENT_DIR [unittest options]

Each test runs on a ROS_DOMAIN_ID of its own, pinned to the loopback, as nodes_test.py's."""
import os
import signal
import sys
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ros2_peer_test as peers  # noqa: E402
from domains import domain  # noqa: E402
from nodes_test import HERE, gone, node_profile, package, string_port, wait_until  # noqa: E402
from std_msgs.msg import String  # noqa: E402

SCRIPT = (HERE / "nodes" / "lifecycle_talker.py").read_text()


LEVEL = ("<data_port><name>level</name><usage>output</usage><data_type>std_msgs/msg/Float64</data_type>"
         '<topic>/demo/level</topic><validity field="data"><min>0</min><max>10</max></validity></data_port>')


def managed(parameters=(), lifecycle="<lifecycle/>", node="/demo/managed", namespace="/demo"):
    ports = string_port("chatter", f"{namespace}/chatter") + LEVEL.replace("/demo/", f"{namespace}/")
    return node_profile("Managed", "python3 lifecycle_talker.py", node, [("greeting", "hi"), *parameters], ports,
                        extra=lifecycle)


def run_managed(test, d, profile=None, policy="<severity>reset</severity>"):
    files = {"managed.xml": profile or managed(), "lifecycle_talker.py": SCRIPT}
    return peers.KeelRun(test, d, package(ref="managed.xml", policy=policy), files)


def standby_package(count=1, policy="<severity>reset</severity>", intensity=1000):
    """The managed talker as subcomponent `talker`, with `count` standbys."""
    return ('<?xml version="1.0"?>\n<package_profile><name>standby_test</name><subcomponents><subcomponent>'
            f'<name>talker</name><reference>managed.xml</reference><process name="talker" standby="{count}"/>'
            f"<fault_policy>{policy}<restart intensity=\"{intensity}\" period=\"60000\"/></fault_policy>"
            "</subcomponent></subcomponents></package_profile>\n")


def run_with_standby(test, d, profile=None, count=1):
    files = {"managed.xml": profile or managed(), "lifecycle_talker.py": SCRIPT}
    return peers.KeelRun(test, d, standby_package(count), files)


class Writers:
    """The pids of the writers a subscriber of /demo/chatter hears, in the order heard; `mixed()`
    says whether a writer was heard after another had taken over from it (two active at once)."""

    def __init__(self, test, d):
        self.peer = peers.Ros2Peer(test, d)
        self.pids = []
        self.peer.node.create_subscription(String, "/demo/chatter", lambda m: self.pids.append(int(m.data.split()[2])),
                                           100)

    def spin_until(self, pred, seconds):
        return self.peer.spin_until(pred, seconds)

    def order(self):
        order = []
        for pid in self.pids:
            if not order or order[-1] != pid:
                order.append(pid)
        return order

    def mixed(self):
        return len(self.order()) != len(set(self.order()))


def node_records(run, phase=None, component=None):
    return [r for r in run.records() if r.get("event") == "node" and (phase is None or r.get("phase") == phase)
            and (component is None or r.get("component") == component)]


def faults(run):
    return [r for r in run.records() if r.get("event") == "detected"]


def said(run, what, files="log.talker*.out"):
    """The node's own lines `lifecycle <what> <pid>` so far, as pids, from each of its processes'
    output files (a standby's is a file of its own name)."""
    return [int(line.split()[2]) for out in sorted(run.dir.glob(files))
            for line in out.read_text().splitlines() if line.startswith(f"lifecycle {what} ")]


class StartAndStop(unittest.TestCase):
    def test_keel_configures_and_activates_the_node_and_deactivates_and_shuts_it_down_at_stop(self):
        """Started Unconfigured, the node is configured then activated by keel (each a `node`
        record once its transition event confirms it) and publishes; at keel run's end it is
        deactivated and shut down before its process is signalled."""
        d = domain()
        run = run_managed(self, d)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [configured] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "configured", 30,
                                    "its configuration")
        [activated] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30,
                                   "its activation")
        self.assertEqual(configured["pid"], started["pid"])
        self.assertLess(configured["t_ns"], activated["t_ns"])
        self.assertEqual(said(run, "configure"), [started["pid"]])
        self.assertEqual(said(run, "activate"), [started["pid"]])
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(String, "/demo/chatter", lambda m: heard.append(m.data), 10)
        self.assertTrue(peer.spin_until(lambda: any(h.startswith("hi ") for h in heard), 30), f"heard: {heard}")
        run.stop()
        phases = [r["phase"] for r in node_records(run)]
        self.assertEqual(phases[-3:], ["deactivated", "shut_down", "stopped"], phases)
        self.assertEqual(said(run, "deactivate"), [started["pid"]])
        self.assertEqual(said(run, "shutdown"), [started["pid"]])
        self.assertTrue(gone(started["pid"]))
        self.assertEqual([r for r in run.records() if r.get("event") == "detected"], [])

    def test_a_node_is_configured_only_once_the_managed_node_it_needs_is_active_and_wound_down_before_it(self):
        """`planner` needs `driver` (<needs>): the planner is configured only after the driver
        is activated, and at the end deactivated before the driver is."""
        d = domain()
        pkg = ('<?xml version="1.0"?>\n<package_profile><name>order</name><subcomponents>'
               "<subcomponent><name>planner</name><reference>planner.xml</reference></subcomponent>"
               "<subcomponent><name>driver</name><reference>driver.xml</reference></subcomponent>"
               '</subcomponents><coordination><needs source="planner" target="driver"/></coordination>'
               "</package_profile>\n")
        # The driver slow to configure: without the order, the planner would be active seconds first.
        files = {"planner.xml": managed(node="/a/planner", namespace="/a"),
                 "driver.xml": managed([("configure_ms", "3000")], node="/b/driver", namespace="/b"),
                 "lifecycle_talker.py": SCRIPT}
        run = peers.KeelRun(self, d, pkg, files)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated"
                     and r.get("component") == "planner", 40, "the planner active")
        driver_active = node_records(run, "activated", "driver")
        [planner_configured] = node_records(run, "configured", "planner")
        self.assertEqual(len(driver_active), 1, "the planner was active before the driver")
        self.assertLess(driver_active[0]["t_ns"], planner_configured["t_ns"])
        run.stop()
        [planner_down] = node_records(run, "deactivated", "planner")
        [driver_down] = node_records(run, "deactivated", "driver")
        self.assertLess(planner_down["t_ns"], driver_down["t_ns"])


class Faults(unittest.TestCase):
    def test_a_failed_on_configure_is_a_lifecycle_fault_saying_where_the_node_is(self):
        """on_configure returns FAILURE (the node back to Unconfigured), and in another run
        raises (through ErrorProcessing): each a `lifecycle` fault of the node; stopped by its
        policy, it is then signalled (nothing to deactivate)."""
        for parameter, words in (("fail_configure", "configure failed: it is unconfigured"),
                                 ("error_configure", "configure failed with an error: it is unconfigured")):
            with self.subTest(parameter=parameter):
                run = run_managed(self, domain(), managed([(parameter, "true")]),
                                  policy="<severity>stop</severity>")
                [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20,
                                         "its start")
                [fault] = run.wait_for(lambda r: r.get("event") == "detected", 30, "the failed configure")
                self.assertEqual((fault["kind"], fault["component"]), ("lifecycle", "talker"), fault)
                self.assertIn(f"node '/demo/managed': {words}", fault["detail"])
                run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "stopped", 20, "its stop")
                self.assertEqual(said(run, "activate"), [])
                self.assertEqual(said(run, "configure"), [started["pid"]])
                run.stop()

    def test_a_transition_that_times_out_is_a_lifecycle_fault_and_its_reset_restarts_the_process(self):
        """on_configure takes 3 s where the profile allows 1 s: a `lifecycle` fault naming the
        transition and the time; the node did not answer in time, so its reset is a restart (a
        new process), which is configured and activated in turn."""
        d = domain()
        profile = managed([("configure_ms", "3000")], lifecycle='<lifecycle transition_timeout="1000"/>')
        run = run_managed(self, d, profile)
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 30, "the late configure")
        self.assertEqual(fault["kind"], "lifecycle")
        self.assertIn("node '/demo/managed': configure not done within 1000 ms: it is configuring", fault["detail"])
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "its restart")
        self.assertNotEqual(again["pid"], started["pid"])
        run.stop()

    def test_a_node_that_finalizes_itself_is_a_lifecycle_fault_and_is_restarted(self):
        """The node shuts itself down at its 5th message (Finalized, its process alive): a
        `lifecycle` fault; no transition leads back from Finalized, so its reset restarts it."""
        d = domain()
        run = run_managed(self, d, managed([("finalize_at", "5")]))
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 30, "its shutdown by itself")
        self.assertEqual(fault["kind"], "lifecycle")
        self.assertIn("node '/demo/managed' went from shuttingdown to finalized by itself", fault["detail"])
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "its restart")
        self.assertNotEqual(again["pid"], started["pid"])
        run.stop()


class Reset(unittest.TestCase):
    def test_a_live_node_faulty_by_its_values_is_reset_by_transitions_in_the_same_process(self):
        """The node's 10th level reads 100 where its profile allows [0, 10]: a `range` fault,
        whose reset goes deactivate → cleanup → configure → activate in the same process (its
        pid's own lines say so), and the fault is recovered once it is Active again."""
        d = domain()
        run = run_managed(self, d, managed([("lie_at", "10")]))
        [started] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "started", 20, "its start")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 30, "the lie")
        self.assertEqual(fault["kind"], "range")
        [resetting] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "resetting", 20,
                                   "its reset")
        self.assertEqual(resetting["pid"], started["pid"])
        self.assertIn("deactivate → cleanup → configure → activate, in the same process", resetting["detail"])
        [recovered] = run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"],
                                   30, "its recovery")
        # Recovered once Active again, not when its reset was asked for.
        activated = node_records(run, "activated")
        self.assertEqual(len(activated), 2, activated)
        self.assertGreaterEqual(recovered["t_ns"], activated[1]["t_ns"])
        pid = started["pid"]
        self.assertEqual((said(run, "deactivate"), said(run, "cleanup")), ([pid], [pid]))
        self.assertEqual((said(run, "configure"), said(run, "activate")), ([pid, pid], [pid, pid]))
        self.assertEqual(node_records(run, "restarted"), [])
        peer = peers.Ros2Peer(self, d)
        heard = []
        peer.node.create_subscription(String, "/demo/chatter", lambda m: heard.append(m.data), 10)
        self.assertTrue(peer.spin_until(lambda: len(heard) >= 3, 30), f"heard: {heard}")
        run.stop()
        self.assertEqual(len(faults(run)), 1, faults(run))

    def test_a_killed_node_is_restarted_then_configured_and_activated(self):
        """kill -9 of the active node: a `process` fault, a new process, configured and
        activated by keel, the fault recovered once it is Active."""
        d = domain()
        run = run_managed(self, d)
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30, "active")
        os.kill(active["pid"], signal.SIGKILL)
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 20, "its death")
        self.assertEqual(fault["kind"], "process")
        [again] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "restarted", 20,
                               "its restart")
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated"
                                and r["pid"] == again["pid"], 30, "the new process active")
        [recovered] = run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"],
                                   30, "its recovery")
        self.assertGreaterEqual(recovered["t_ns"], active["t_ns"])  # once Active, not at its start
        run.stop()


class Standby(unittest.TestCase):
    def test_a_standby_is_started_and_configured_and_stays_silent(self):
        """With standby="1": a second process, named /demo/managed_standby_1, configured and left
        Inactive (its own lines: configure, no activate); only the active one is heard. At the
        end the standby is stopped too, and no process is left."""
        d = domain()
        run = run_with_standby(self, d)
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30, "active")
        [ready] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready", 30,
                               "the standby ready")
        self.assertEqual(ready["node"], "/demo/managed_standby_1")
        self.assertNotEqual(ready["pid"], active["pid"])
        self.assertEqual(sorted(said(run, "configure")), sorted([active["pid"], ready["pid"]]))
        self.assertEqual(said(run, "activate"), [active["pid"]])
        # Each process writes to a file of its own name: two processes' lines never interleave.
        self.assertEqual(said(run, "configure", "log.talker.out"), [active["pid"]])
        self.assertEqual(said(run, "configure", "log.talker.managed_standby_1.out"), [ready["pid"]])
        [started] = node_records(run, "standby_started")
        self.assertEqual(started["output"], str(run.dir / "log.talker.managed_standby_1.out"))
        writers = Writers(self, d)
        self.assertTrue(writers.spin_until(lambda: len(writers.pids) >= 10, 30), writers.pids)
        self.assertEqual(set(writers.pids), {active["pid"]})
        run.stop()
        stopped = {r["pid"] for r in node_records(run, "stopped")}
        self.assertEqual(stopped, {active["pid"], ready["pid"]}, node_records(run))
        self.assertTrue(gone(active["pid"]) and gone(ready["pid"]))
        self.assertEqual(faults(run), [])

    def test_a_killed_active_is_taken_over_by_its_standby_and_another_stands_by_behind_it(self):
        """kill -9 of the active: its `process` fault, then the standby promoted (no restart) and
        activated, the fault recovered, a fresh standby started and configured behind it; a
        subscriber hears the old writer, then only the new one."""
        d = domain()
        run = run_with_standby(self, d)
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30, "active")
        [ready] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready", 30,
                               "the standby ready")
        writers = Writers(self, d)
        self.assertTrue(writers.spin_until(lambda: len(writers.pids) >= 3, 30), writers.pids)
        os.kill(active["pid"], signal.SIGKILL)
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 20, "the death")
        self.assertEqual(fault["kind"], "process")
        [promoted] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "promoted", 20,
                                  "the standby promoted")
        self.assertEqual((promoted["pid"], promoted["node"]), (ready["pid"], "/demo/managed_standby_1"))
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated"
                     and r["pid"] == ready["pid"], 20, "the standby active")
        run.wait_for(lambda r: r.get("event") == "recovered" and r.get("fault_id") == fault["fault_id"], 20,
                     "the recovery")
        fresh = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready"
                             and r["pid"] not in (active["pid"], ready["pid"]), 30, "a fresh standby")
        self.assertEqual(fresh[0]["node"], "/demo/managed_standby_2")  # _1 serves now
        self.assertTrue(writers.spin_until(lambda: writers.pids[-1] == ready["pid"], 30), writers.pids)
        self.assertEqual(writers.order(), [active["pid"], ready["pid"]])
        self.assertEqual(node_records(run, "restarted"), [])
        run.stop()

    def test_a_standby_killed_while_standing_by_is_replaced_without_a_fault(self):
        """kill -9 of the standby: a `standby_exited` record, another standby started and
        configured, and no fault: the role was served all along."""
        d = domain()
        run = run_with_standby(self, d)
        [ready] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready", 30,
                               "the standby ready")
        os.kill(ready["pid"], signal.SIGKILL)
        [exited] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_exited", 20,
                                "its exit")
        self.assertIn("killed by signal 9", exited["detail"])
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready"
                     and r["pid"] != ready["pid"], 30, "another standby")
        self.assertEqual(node_records(run, "promoted"), [])
        run.stop()
        self.assertEqual(faults(run), [])

    def test_promotions_count_against_the_restart_intensity_and_escalate_past_it(self):
        """With at most one recovery a minute: the first kill is taken over by the standby; the
        second, within the minute, escalates past `reset` to a fault stop: no promotion, the
        node and its standby ended."""
        d = domain()
        files = {"managed.xml": managed(), "lifecycle_talker.py": SCRIPT}
        run = peers.KeelRun(self, d, standby_package(intensity=1), files)
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30, "active")
        [ready] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready", 30,
                               "the standby ready")
        os.kill(active["pid"], signal.SIGKILL)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated"
                     and r["pid"] == ready["pid"], 20, "the standby active")
        [fresh] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready"
                               and r["pid"] not in (active["pid"], ready["pid"]), 30, "a fresh standby")
        os.kill(ready["pid"], signal.SIGKILL)
        [escalated] = run.wait_for(lambda r: r.get("event") == "action" and r.get("fault_id") == 2, 20,
                                   "the second fault's handling")
        self.assertEqual((escalated["action"], escalated["detail"]),
                         ("escalate", "reset → stop: more than 1 recoveries within 60000 ms"), escalated)
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") in ("stopped", "standby_exited")
                     and r["pid"] == fresh["pid"], 20, "the fresh standby ended")
        self.assertEqual(len(node_records(run, "promoted")), 1, node_records(run, "promoted"))
        self.assertTrue(gone(fresh["pid"]))
        run.stop()

    def test_a_live_faulty_active_is_deactivated_before_its_standby_is_activated(self):
        """The active's 40th level (4 s after its activation) is out of range: a `range` fault,
        whose reset is the standby's promotion, the faulty one deactivated first (its own line)
        and then ended; never two writers heard at once."""
        d = domain()
        run = run_with_standby(self, d, managed([("lie_at", "40")]))
        [active] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30, "active")
        writers = Writers(self, d)
        # The standby ready before the lie (its configure may wait a resend, a second): else
        # the reset is the one without a standby, as it should be, and not this test's.
        [ready] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready", 30,
                               "the standby ready")
        [fault] = run.wait_for(lambda r: r.get("event") == "detected", 30, "the lie")
        self.assertLess(ready["t_ns"], fault["t_ns"], "the standby was not ready before the lie")
        self.assertEqual(fault["kind"], "range")
        [promoted] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "promoted", 20,
                                  "the standby promoted")
        self.assertIn(f"in place of pid {active['pid']} (/demo/managed), deactivated, then ended", promoted["detail"])
        self.assertEqual(said(run, "deactivate"), [active["pid"]])
        run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "stopped"
                     and r["pid"] == active["pid"], 20, "the faulty one ended")
        self.assertTrue(writers.spin_until(lambda: writers.pids and writers.pids[-1] == promoted["pid"], 30),
                        writers.pids)
        self.assertFalse(writers.mixed(), writers.order())
        run.stop()


class StandbyCampaign(unittest.TestCase):
    def test_every_kill_9_of_the_active_is_taken_over_by_a_standby_and_never_two_write(self):
        """KEEL_NODE_KILL_CAMPAIGN kills (default 100) of the active, each once a standby is
        ready: every one a `process` fault, a promotion of the ready standby, recovered; the
        subscriber never hears a writer after the one that took over from it; the log complete
        (a promotion and a fresh standby per kill)."""
        kills = int(os.environ.get("KEEL_NODE_KILL_CAMPAIGN", "100"))
        d = domain()
        files = {"managed.xml": managed(), "lifecycle_talker.py": SCRIPT}
        run = peers.KeelRun(self, d, standby_package(), files, duration=60 + 5 * kills)
        writers = Writers(self, d)
        serving = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated", 30,
                               "the first active")[0]["pid"]
        promoted = set()
        for i in range(kills):
            run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "standby_ready"
                         and r["pid"] != serving and not gone(r["pid"]), 30, f"kill {i}: a standby ready")
            self.assertTrue(writers.spin_until(lambda: writers.pids and writers.pids[-1] == serving, 30),
                            f"kill {i}: the active {serving} not heard")
            os.kill(serving, signal.SIGKILL)
            [took] = run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "promoted"
                                  and r["pid"] not in promoted, 20, f"kill {i}: the promotion")
            promoted.add(took["pid"])
            serving = took["pid"]
            run.wait_for(lambda r: r.get("event") == "node" and r.get("phase") == "activated" and r["pid"] == serving,
                         20, f"kill {i}: the standby active")
        run.wait_for(lambda r: r.get("event") == "recovered"
                     and sum(x.get("event") == "recovered" for x in run.records()) >= kills, 30, "every recovery")
        self.assertTrue(writers.spin_until(lambda: writers.pids and writers.pids[-1] == serving, 30))
        run.stop()
        detected = faults(run)
        self.assertEqual([f["kind"] for f in detected], ["process"] * kills, detected)
        self.assertEqual(len(node_records(run, "promoted")), kills)
        self.assertEqual(node_records(run, "restarted"), [])
        self.assertFalse(writers.mixed(), writers.order())


if __name__ == "__main__":
    peers.KEEL, peers.COMPONENTS = sys.argv[1], sys.argv[2]  # keel, tests/dds/components.cpp's library
    os.environ["FASTDDS_DEFAULT_PROFILES_FILE"] = str(HERE / "fastdds-lo.xml")
    unittest.main(argv=[sys.argv[0]] + sys.argv[3:], verbosity=2)
