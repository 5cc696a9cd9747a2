// Reads a profile file and everything it references (component, composite, package and system
// profiles, docs/profiles.md) and validates the whole before anything runs. Every problem found is
// reported, each as `file:line: message`. Knows nothing of threads or dlopen.
// Thread-safety: free functions over their own data; safe to call concurrently.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "profile/model.hpp"

namespace keel::profile {

/// One problem in a profile.
struct Diagnostic {
  Where where;
  std::string message;
  /// "file:line: message" (line omitted when 0).
  std::string str() const;
  /// "file:line: warning: message".
  std::string warningStr() const;
};

using Diagnostics = std::vector<Diagnostic>;

enum class RootKind {
  Component,
  Composite,
  Package,
  System,
  ServiceType,   // OPRoS <service_port_type_profile>
  DataType,      // OPRoS <data_type>
  EngineConfig,  // OPRoS <system_config>: an engine's configuration, not run
  Node,          // <ros2_node_profile>: a ROS 2 node
};

/// Everything reachable from one root profile, keyed by absolute file path.
struct ProfileSet {
  RootKind root_kind = RootKind::Package;
  std::string root;  // absolute path of the root file
  std::map<std::string, ComponentProfile> components;
  std::map<std::string, CompositeProfile> composites;
  std::map<std::string, PackageProfile> packages;
  std::optional<SystemProfile> system;
  std::map<std::string, ServiceTypeProfile> service_types;
  std::map<std::string, DataTypeProfile> data_types;
  /// Node profiles, by path. Each node's `component` is also in `components` under the same
  /// path, so that a subcomponent referencing a node is, to everything that assembles and
  /// checks components, a passive component with the node's ports.
  std::map<std::string, NodeProfile> nodes;
  /// What loads but has no effect in this keel, each `file:line: message` (docs/profiles.md):
  /// the run goes on, and `keel run` and `keel validate` print them as warnings.
  Diagnostics warnings;

  const PackageProfile* rootPackage() const;
};

/// Loads and validates `path` and all it references. On failure, every problem found.
Result<ProfileSet, Diagnostics> load(const std::string& path);

/// The name of `path`'s root element, without checking anything else; empty when the file
/// cannot be read or parsed (load() then says why).
std::string rootElementName(const std::string& path);

}  // namespace keel::profile
