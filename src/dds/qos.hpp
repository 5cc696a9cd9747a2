// ROS 2's QoS profiles by name, and a binding's deadline and liveliness, as CycloneDDS QoS
// (docs/dds.md#qos). Thread-safety: functions of their arguments.
#pragma once

#include <dds/dds.h>

#include <memory>
#include <optional>

#include "profile/model.hpp"

namespace keel::dds {

struct QosDeleter {
  void operator()(dds_qos_t* q) const { dds_delete_qos(q); }
};
using Qos = std::unique_ptr<dds_qos_t, QosDeleter>;

/// The QoS of `b`'s writer (publish) or reader (subscribe): the profile named by its `qos`,
/// its depth, the deadline and liveliness it offers or requests, and its ownership: a reader's
/// `ownership="exclusive"`, or the `redundancy` of the component a writer belongs to.
Qos qosOf(const profile::DdsBinding& b, const std::optional<profile::Redundancy>& redundancy = std::nullopt);

/// ROS 2's name of the QoS policy `id` (DDS_..._QOS_POLICY_ID), for messages: "reliability".
const char* policyName(dds_qos_policy_id_t id);

}  // namespace keel::dds
