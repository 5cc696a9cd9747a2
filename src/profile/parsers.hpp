// The per-file profile parsers: one XML root element in, one plain struct out (model.hpp),
// every problem of that file reported through the Ctx, references to other profiles recorded
// in the Ctx for the loader to follow. Checks that need another file live in validate.hpp.
// Called by loader.cpp. Thread-safety: functions of their arguments.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "profile/model.hpp"
#include "profile/xml_reader.hpp"

namespace keel::profile::detail {

// Roots (component_profile.cpp, composite_profile.cpp, package_profile.cpp, system_profile.cpp).
void parseComponentProfile(Ctx& ctx, pugi::xml_node root, ComponentProfile& out);
void parseCompositeProfile(Ctx& ctx, pugi::xml_node root, CompositeProfile& out);
void parsePackageProfile(Ctx& ctx, pugi::xml_node root, PackageProfile& out);
void parseSystemProfile(Ctx& ctx, pugi::xml_node root, SystemProfile& out);
// A ROS 2 node (node_profile.cpp; its ports and <emergency>: node_ports.cpp).
void parseNodeProfile(Ctx& ctx, pugi::xml_node root, NodeProfile& out);
// OPRoS's type profiles and engine configuration (type_profiles.cpp).
void parseServiceTypeProfile(Ctx& ctx, pugi::xml_node root, ServiceTypeProfile& out);
void parseDataTypeProfile(Ctx& ctx, pugi::xml_node root, DataTypeProfile& out);
void parseEngineConfig(Ctx& ctx, pugi::xml_node root);

// Pieces shared by several roots.
/// <execution_semantics> (component_profile.cpp).
Execution parseExecution(Ctx& ctx, pugi::xml_node node, const std::string& owner);
/// <properties> of a component profile: name, type and typed value (component_profile.cpp).
std::vector<Property> parseProperties(Ctx& ctx, pugi::xml_node node, const std::string& owner);
/// <ports> (ports.cpp).
void parsePorts(Ctx& ctx, pugi::xml_node node, ComponentProfile& out);
/// <validity> of port `owner` (ports.cpp). `field`: the rule names the checked field of the
/// port's message in a required attribute `field`.
Validity parseValidity(Ctx& ctx, pugi::xml_node node, const std::string& owner, bool field = false);
/// One <validity> of data port `p` (ports.cpp): the whole value's, once, or with `field=".."`
/// one of its message's fields, each field once. `field_only`: a node's port, whose every
/// <validity> names a field.
void readValidity(Ctx& ctx, pugi::xml_node node, const std::string& owner, DataPort& p, bool field_only);
/// <ports> of node profile `owner`: its data ports, each on a topic (node_ports.cpp).
void parseNodePorts(Ctx& ctx, pugi::xml_node node, NodeProfile& out, const std::string& owner);
/// <emergency> of node profile `owner`, after its ports (node_ports.cpp).
void parseNodeEmergency(Ctx& ctx, pugi::xml_node node, NodeProfile& out, const std::string& owner);
/// <subcomponents> (subcomponents.cpp). Override values stay untyped strings (type "" unless
/// the attribute gave one) until validation types them against the referenced component.
std::vector<Subcomponent> parseSubcomponents(Ctx& ctx, pugi::xml_node node);
/// <port_connections> (subcomponents.cpp).
std::vector<Connection> parseConnections(Ctx& ctx, pugi::xml_node node);
/// <coordination> of a package or composite (package_profile.cpp).
Coordination parseCoordination(Ctx& ctx, pugi::xml_node node);
/// Why an application's or composite's <app_domain> and <execution_environment> are not used.
inline constexpr std::string_view kNoAppDomain = "OPRoS's engine read it and did nothing with it";
inline constexpr std::string_view kNoAssemblyEnvironment =
    "each component profile's <execution_environment> names its library";
/// The children of an assembly's profile (package, composite, system): its own, then those they
/// all read alike — name, description, port_connections, and the OPRoS IDE's id, version and
/// copyright, which keel keeps nowhere (package_profile.cpp). `connections`: where its
/// port_connections go.
std::vector<Child> assemblyChildren(Ctx& ctx, std::string& name, std::string& description,
                                    std::vector<Connection>& connections, std::initializer_list<Child> own);
/// <dds> of a package or system profile (dds_profile.cpp).
DdsSpec parseDds(Ctx& ctx, pugi::xml_node node);
/// <fault_policy> of subcomponent `owner` (fault_policy.cpp).
FaultPolicy parseFaultPolicy(Ctx& ctx, pugi::xml_node node, const std::string& owner);

/// The text of a required child that was not given: "missing <name> in <data_port>".
void reportMissing(Ctx& ctx, pugi::xml_node parent, std::string_view child, const std::string& owner = {});

}  // namespace keel::profile::detail
