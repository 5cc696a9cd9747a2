// ROS 2's QoS profiles as rclpy/rclcpp define them (qos.hpp).
#include "dds/qos.hpp"

namespace keel::dds {

Qos qosOf(const profile::DdsBinding& b, const std::optional<profile::Redundancy>& redundancy) {
  Qos q(dds_create_qos());
  dds_qos_t* p = q.get();
  std::int32_t depth = 10;
  switch (b.qos) {
    case profile::DdsQos::Default:  // rclpy QoSProfile(depth=10): reliable, keep last 10, volatile
    case profile::DdsQos::Reliable:
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      break;
    case profile::DdsQos::SensorData:  // qos_profile_sensor_data: best effort, keep last 5, volatile
      dds_qset_reliability(p, DDS_RELIABILITY_BEST_EFFORT, 0);
      dds_qset_durability(p, DDS_DURABILITY_VOLATILE);
      depth = 5;
      break;
    case profile::DdsQos::TransientLocal:  // "latched": reliable, keep last 1, transient local
      dds_qset_reliability(p, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
      dds_qset_durability(p, DDS_DURABILITY_TRANSIENT_LOCAL);
      depth = 1;
      break;
  }
  if (b.depth) depth = static_cast<std::int32_t>(*b.depth);
  dds_qset_history(p, DDS_HISTORY_KEEP_LAST, depth);
  if (b.deadline_ms) dds_qset_deadline(p, static_cast<dds_duration_t>(*b.deadline_ms * 1e6));
  if (b.liveliness_ms)
    dds_qset_liveliness(p, DDS_LIVELINESS_AUTOMATIC, static_cast<dds_duration_t>(*b.liveliness_ms * 1e6));
  // XCDR1, as ROS 2 writes: a reader accepts nothing else, so a writer offering XCDR2 does not
  // match (CycloneDDS 0.10 reads past a truncated XCDR2 sample's 8-byte fields: docs/fuzzing.md).
  const dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(p, 1, xcdr1);
  if (b.exclusive || redundancy) dds_qset_ownership(p, DDS_OWNERSHIP_EXCLUSIVE);
  if (redundancy) dds_qset_ownership_strength(p, redundancy->strength);  // the strongest live writer is heard
  return q;
}

const char* policyName(dds_qos_policy_id_t id) {
  switch (id) {
    case DDS_DURABILITY_QOS_POLICY_ID: return "durability";
    case DDS_DEADLINE_QOS_POLICY_ID: return "deadline";
    case DDS_LIVELINESS_QOS_POLICY_ID: return "liveliness";
    case DDS_RELIABILITY_QOS_POLICY_ID: return "reliability";
    case DDS_OWNERSHIP_QOS_POLICY_ID: return "ownership";
    case DDS_HISTORY_QOS_POLICY_ID: return "history";
    case DDS_DATA_REPRESENTATION_QOS_POLICY_ID: return "data representation";
    default: return "a QoS policy";
  }
}

}  // namespace keel::dds
