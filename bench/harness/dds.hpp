// `keel bench dds`: keel's DDS ports (docs/dds.md) measured as a user runs them — `keel run`s
// the harness starts on profiles it writes, over the benchmark's components
// (bench/components/dds_components.cpp) — beside a plain CycloneDDS C program doing the same
// (bench/peers/dds_raw.c: keel-bench-dds-raw) and rclpy's (bench/peers/rclpy_pingpong.py, for the
// record), all in one run, with the same message (std_msgs/msg/Header), topics and QoS
// (reliable, keep last 10, volatile):
//   roundtrip_keel   a keel run's periodic component stamps a Header every millisecond onto a
//                    topic; a second keel run's aperiodic component echoes it onto another; the
//                    first's aperiodic sink takes it: arrival − stamp
//   roundtrip_raw    the same with keel-bench-dds-raw's ping and pong (a WaitSet thread each)
//   roundtrip_rclpy  the same with rclpy's ping and pong (Fast DDS), when a python with rclpy is
//                    found (KEEL_RCLPY_PYTHON, else python3)
//   remote           a keel subscriber with `deadline` D (in the harness's process, the real
//                    engine); keel-bench-dds-raw writing every millisecond is killed with kill -9:
//                    keel's `remote` fault's detection − the kill
//   failover         `<redundancy>` across two hosts (two network namespaces and a veth pair, made
//                    here; root): a primary and a standby keel run write every millisecond with a
//                    liveliness lease L, a third keel run reads with ownership="exclusive"; kill -9
//                    of the primary's run: the standby's first sample at the reader − the kill
// The two round trips alternate in chunks, so that the machine's drift weighs on both alike.
// Every keel run and DDS program of a cell is on one domain (ROS_DOMAIN_ID, else one from the
// pid) and, but for failover, CycloneDDS pinned to the loopback (as keel's tests run it).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "paths.hpp"
#include "process.hpp"

namespace keel::bench {

struct DdsCell {
  std::vector<std::int64_t> latencies_ns;
  std::size_t failed = 0;  // trials that did not end within their bound
  std::string error;       // non-empty: the cell could not run (all of it, or its rest)
  std::string note;        // what ran, when it says more than the cell's name
};

// CycloneDDS on the loopback alone, peers found by unicast (the machine may have no
// multicast-capable interface), as keel's tests run it; also `keel bench isolation`'s ddsperf.
inline constexpr std::string_view kCycloneLoopbackConfig = R"(<CycloneDDS>
  <Domain id="any">
    <General>
      <Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
      <AllowMulticast>false</AllowMulticast>
    </General>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <MaxAutoParticipantIndex>30</MaxAutoParticipantIndex>
      <Peers><Peer address="127.0.0.1"/></Peers>
    </Discovery>
  </Domain>
</CycloneDDS>
)";

inline constexpr int kRemoteDeadlineMs = 50;  // remote: the subscription's deadline
inline constexpr int kFailoverLeaseMs = 200;  // failover: the writers' liveliness lease

/// The environment of a `keel bench dds` run: CycloneDDS pinned to the loopback, Fast DDS too
/// (rclpy), and a domain; set for this process and every process it starts until it goes.
class DdsEnvironment {
 public:
  DdsEnvironment();
  ~DdsEnvironment() = default;
  DdsEnvironment(const DdsEnvironment&) = delete;
  DdsEnvironment& operator=(const DdsEnvironment&) = delete;
  DdsEnvironment(DdsEnvironment&&) = delete;
  DdsEnvironment& operator=(DdsEnvironment&&) = delete;
  int domain() const { return domain_; }

 private:
  TempDir dir_;  // the configurations, removed after every process that reads them
  int domain_ = 0;
};

// What the dds cells share with the ros2 cells (ros2.hpp).
/// The benchmark's three components (BenchDdsStamp, BenchDdsEcho, BenchDdsSink: ports of
/// std_msgs/msg/Header), their profiles on `page`: file name → text.
std::vector<std::pair<std::string, std::string>> componentFiles(const std::string& page);
/// A package of `subcomponents` (XML) with `<dds>` `bindings`.
std::string packageXml(const std::string& name, const std::string& subcomponents, const std::string& bindings);
/// `<subcomponent>` `name` of profile `type`.xml, with `more` inside it.
std::string subcomponent(const char* name, const char* type, const std::string& more = "");
/// A `<publish>` or `<subscribe>` (`kind`) of a std_msgs/msg/Header port on `topic`; `more`: its attributes.
std::string binding(const char* kind, const char* component, const char* port_name, const std::string& topic,
                    const std::string& more = "");
/// A python with rclpy: KEEL_RCLPY_PYTHON, else python3 if it imports rclpy; empty otherwise.
std::string rclpyPython();

/// `n` round trips, 1 kHz, between two keel runs.
DdsCell measureKeelRoundTrip(const Paths& paths, int n);
/// `n` round trips, 1 kHz, between keel-bench-dds-raw's ping and pong.
DdsCell measureRawRoundTrip(const Paths& paths, int n);
/// `n` round trips, 1 kHz, between rclpy's ping and pong.
DdsCell measureRclpyRoundTrip(const Paths& paths, int n);
/// `n` kills of a writer a keel subscriber watches with a deadline of kRemoteDeadlineMs.
DdsCell measureRemoteDetection(const Paths& paths, int n);
/// `n` kills of the primary of a redundant pair across two hosts (network namespaces).
DdsCell measureFailover(const Paths& paths, int n);

}  // namespace keel::bench
