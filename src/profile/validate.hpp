// Cross-file validation of a loaded ProfileSet: names within packages and composites,
// property overrides (typed here against the referenced component), port connections and
// exports, tasks, coordination, alternatives and the system profile. Every problem is
// reported; nothing stops at the first. Called by loader.cpp once every file is parsed.
// Thread-safety: functions of their arguments.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "profile/loader.hpp"
#include "profile/model.hpp"

namespace keel::profile::detail {

/// Runs every check below over `set` (overrides are typed in place).
void validate(ProfileSet& set, Diagnostics& diags);

// validate_assembly.cpp: subcomponents, overrides, tasks, depends.
void checkSubcomponents(ProfileSet& set, std::vector<Subcomponent>& subs, Diagnostics& diags);
void checkTasks(const ProfileSet& set, const PackageProfile& pkg, Diagnostics& diags);
/// <coordination>'s depends and needs (names, duplicates, cycles); warnings for an execution
/// order with a passive end.
void checkCoordination(ProfileSet& set, const std::vector<Subcomponent>& subs, const Coordination& coordination,
                       Diagnostics& diags);
/// Warnings (set.warnings) for fault_policy settings that load but have no effect.
/// `dds`: the <dds> of the same profile (null: none).
void checkIneffectivePolicies(ProfileSet& set, const std::vector<Subcomponent>& subs, const DdsSpec* dds);

// validate_ports.cpp: connections, exports, alternatives.
void checkConnections(const ProfileSet& set, const std::vector<Subcomponent>& subs,
                      std::vector<Connection>& connections, Diagnostics& diags);
void checkExports(const ProfileSet& set, const CompositeProfile& composite, Diagnostics& diags);
/// A <dds>'s bindings: the port exists, is a data port of the right direction, its data_type is
/// the topic's type.
void checkDds(const ProfileSet& set, const std::vector<Subcomponent>& subs, const DdsSpec& dds, Diagnostics& diags);
void checkAlternatives(const ProfileSet& set, const std::vector<Subcomponent>& subs, Diagnostics& diags);

// validate_system.cpp (connections between applications typed in place, as a package's).
void checkSystem(const ProfileSet& set, SystemProfile& system, Diagnostics& diags);

// Helpers shared by the checks.

/// One port as seen from outside a (possibly composite) component.
/// keel's own system component, always present: the fault manager and its FaultEvent input.
inline constexpr std::string_view kFaultManager = "fault_manager";
inline constexpr std::string_view kFaultManagerPort = "faults";

struct PortSig {
  std::string name;
  PortKind kind = PortKind::Data;
  bool source_side = false;  // output or required service: may be a connection's source
  std::string usage;         // input, output, provided, required
  std::string type;          // data_type, or the service type
  std::string type_profile;  // a service port's service type profile (absolute path), or ""
};

// validate_types.cpp: ports against the OPRoS type profiles they reference (warnings), and a
// service connection's methods against both ends' service types (errors).
void checkTypeReferences(ProfileSet& set);
void checkServiceMethods(const ProfileSet& set, const Connection& c, const PortSig& src, const PortSig& dst,
                         Diagnostics& diags);
/// Whether two C++ type names written in profiles name one type: spaces and `std::` aside
/// (OPRoS's profiles write `std::vector<X>` and `vector< X >` for one type).
bool sameCppType(std::string_view a, std::string_view b);

/// The ports offered by the profile at `path`: an atomic component's ports or a composite's
/// exported ports; nullopt if `path` was not loaded as either.
std::optional<std::vector<PortSig>> portsOf(const ProfileSet& set, const std::string& path, int depth = 0);

/// "data port 'range' (input, data_type 'double')"-style description of a port.
std::string describe(const PortSig& p);

const Subcomponent* findSubcomponent(const std::vector<Subcomponent>& subs, const std::string& name);
/// "a, b, c", or "none".
std::string nameList(const std::vector<std::string>& names);
std::string subcomponentNames(const std::vector<Subcomponent>& subs);
/// The display name of a referenced profile: the component/composite name, or its path.
std::string profileName(const ProfileSet& set, const std::string& path);

/// A dependency graph in declaration order; each edge carries where it was declared.
struct Edge {
  std::string to;
  Where where;
};
using Graph = std::vector<std::pair<std::string, std::vector<Edge>>>;

/// Reports "circular dependency: a -> b -> a" for each cycle found by a depth-first search
/// (one per closing edge, at that edge).
void reportCycles(const Graph& graph, Diagnostics& diags);

}  // namespace keel::profile::detail
