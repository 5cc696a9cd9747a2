// <validity field=".."> against the message types keel has (type_registry.hpp): each rule of a
// data port resolved in the table of fields of its message type, or a `file:line` line per rule
// that names no numeric field, or per port whose type is not a message keel has. Used where a
// rule is set on a port (the engine), where a node's rules are checked, and by keel validate.
// Thread-safety: reads the registry only.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "keel/detail/dds_type.hpp"
#include "keel/result.hpp"
#include "profile/model.hpp"
#include "runtime/field_rules.hpp"

namespace keel::dds {

/// The field rules of data port `port`, resolved in the message type `type`; null: `type_name`
/// (the port's type) is not a message keel has. The error has one line per problem, each
/// `file:line: <who><validity field=".."> of data port 'p': why` ending in '\n'; `who` is
/// "component 'x': " or empty.
Result<std::vector<runtime::FieldRule>> resolveFieldRules(const detail::DdsType* type, std::string_view type_name,
                                                          const profile::DataPort& port, std::string_view who);

/// The same for a port known only by its profile: its data_type looked up in the registry.
/// `unknown_ok`: a data_type that is not registered is no problem (keel validate without
/// --load, where a user's messages are not loaded yet).
Result<std::vector<runtime::FieldRule>> resolveFieldRules(const profile::DataPort& port, std::string_view who,
                                                          bool unknown_ok);

}  // namespace keel::dds
