// OPRoS's type profiles in use (docs/opros.md#type-profiles): a port's <reference> names its
// service type or data type profile. OPRoS's engine never opened those files, so a port that
// disagrees with its own type profile is a warning; a service connection whose ends' service
// types disagree on a method is an error, as keel could not make the calls the caller expects.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "profile/field_reader.hpp"
#include "profile/validate.hpp"

namespace keel::profile::detail {
namespace {

std::string squeeze(std::string_view t) {
  std::string out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t.substr(i).starts_with("std::")) {
      i += 4;
      continue;
    }
    if (t[i] != ' ' && t[i] != '\t') out += t[i];
  }
  return out;
}

std::string signature(const ServiceMethod& m) {
  std::string params;
  for (const auto& [name, type] : m.params) params += (params.empty() ? "" : ", ") + type;
  return fmt::format("{} {}({}){}", m.return_type, m.name, params, m.blocking ? "" : " nonblocking");
}

bool sameSignature(const ServiceMethod& a, const ServiceMethod& b) {
  if (!sameCppType(a.return_type, b.return_type) || a.blocking != b.blocking || a.params.size() != b.params.size())
    return false;
  for (std::size_t i = 0; i < a.params.size(); ++i)
    if (!sameCppType(a.params[i].second, b.params[i].second)) return false;
  return true;
}

std::string fileName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

/// `path` as seen from the folder of the file `from` names (a Where's file, as displayed).
std::string seenFrom(const std::string& path, const std::string& from) {
  std::error_code ec;
  const auto dir = std::filesystem::absolute(from, ec).parent_path();
  auto rel = std::filesystem::path(path).lexically_relative(dir);
  return ec || rel.empty() ? path : rel.string();
}

}  // namespace

bool sameCppType(std::string_view a, std::string_view b) { return a == b || squeeze(a) == squeeze(b); }

void checkTypeReferences(ProfileSet& set) {
  for (const auto& [path, c] : set.components) {
    for (const ServicePort& p : c.service_ports) {
      const auto t = set.service_types.find(p.reference);
      if (t == set.service_types.end() || t->second.name == p.type) continue;
      set.warnings.push_back(
          Diagnostic{p.where,
                     fmt::format("service port '{}' of component '{}' has <type> '{}', but its <reference> '{}' is "
                                 "service type '{}'",
                                 p.name, c.name, p.type, fileName(p.reference), t->second.name)});
    }
    for (const DataPort& p : c.data_ports) {
      const auto t = set.data_types.find(p.reference);
      if (t == set.data_types.end()) continue;
      const auto& structs = t->second.structs;
      if (std::any_of(structs.begin(), structs.end(),
                      [&](const DataTypeProfile::Struct& s) { return sameCppType(s.name, p.data_type); }))
        continue;
      std::vector<std::string> names;
      names.reserve(structs.size());
      for (const auto& s : structs) names.push_back(s.name);
      set.warnings.push_back(
          Diagnostic{p.where,
                     fmt::format("data port '{}' of component '{}' has <data_type> '{}', but its <reference> '{}' "
                                 "defines {}",
                                 p.name, c.name, p.data_type, fileName(p.reference), nameList(names))});
    }
  }
}

void checkServiceMethods(const ProfileSet& set, const Connection& c, const PortSig& src, const PortSig& dst,
                         Diagnostics& diags) {
  const auto caller = set.service_types.find(src.type_profile);
  const auto callee = set.service_types.find(dst.type_profile);
  if (caller == set.service_types.end() || callee == set.service_types.end() || caller == callee) return;
  const std::string caller_file = seenFrom(src.type_profile, c.where.file);
  const std::string callee_file = seenFrom(dst.type_profile, c.where.file);
  for (const ServiceMethod& m : caller->second.methods) {
    const auto& offered = callee->second.methods;
    const auto it = std::find_if(offered.begin(), offered.end(),
                                 [&](const ServiceMethod& o) { return o.name == m.name; });
    if (it == offered.end()) {
      diags.push_back(
          Diagnostic{c.where, fmt::format(
                                  "port_connection: '{}.{}' calls method '{}' ({}), which '{}.{}' does not provide "
                                  "({}: {})",
                                  c.source.component, c.source.port, m.name, caller_file, c.target.component,
                                  c.target.port, callee_file, offered.empty() ? std::string("no methods") : [&] {
                                    std::vector<std::string> names;
                                    names.reserve(offered.size());
                                    for (const auto& o : offered) names.push_back(o.name);
                                    return nameList(names);
                                  }())});
    } else if (!sameSignature(m, *it)) {
      diags.push_back(
          Diagnostic{c.where, fmt::format("port_connection: method '{}' is '{}' in {} ('{}.{}') but "
                                          "'{}' in {} ('{}.{}')",
                                          m.name, signature(m), caller_file, c.source.component, c.source.port,
                                          signature(*it), callee_file, c.target.component, c.target.port)});
    }
  }
}

}  // namespace keel::profile::detail
