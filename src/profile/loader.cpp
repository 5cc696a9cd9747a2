// load(): reads the root profile and, depth first, every profile it references (each file
// once, keyed by its absolute normalised path), detects reference cycles, then runs the
// cross-file validation (validate.hpp). Nothing is thrown out of load(). See loader.hpp.
#include "profile/loader.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "profile/field_reader.hpp"
#include "profile/parsers.hpp"
#include "profile/validate.hpp"

namespace keel::profile {

std::string Diagnostic::str() const {
  if (where.file.empty()) return message;
  if (where.line <= 0) return fmt::format("{}: {}", where.file, message);
  return fmt::format("{}:{}: {}", where.file, where.line, message);
}

std::string Diagnostic::warningStr() const { return Diagnostic{where, "warning: " + message}.str(); }

const PackageProfile* ProfileSet::rootPackage() const {
  if (root_kind != RootKind::Package) return nullptr;
  const auto it = packages.find(root);
  return it == packages.end() ? nullptr : &it->second;
}

namespace detail {
namespace {

namespace fs = std::filesystem;

std::optional<RootKind> rootKindOf(std::string_view element) {
  if (element == "component_profile") return RootKind::Component;
  if (element == "composite_component_profile") return RootKind::Composite;
  if (element == "package_profile" || element == "application_profile") return RootKind::Package;
  if (element == "system_profile") return RootKind::System;
  if (element == "service_port_type_profile") return RootKind::ServiceType;
  if (element == "data_type") return RootKind::DataType;
  if (element == "system_config") return RootKind::EngineConfig;
  if (element == "ros2_node_profile") return RootKind::Node;
  return std::nullopt;
}

std::string kindList(const std::vector<RootKind>& kinds) {
  std::string out;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    if (i > 0) out += (i + 1 == kinds.size()) ? " or " : ", ";
    out += fmt::format("<{}>", name(kinds[i]));
  }
  return out;
}

std::string absolutePath(const std::string& path) {
  std::error_code ec;
  fs::path abs = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) abs = fs::path(path).lexically_normal();
  return abs.string();
}

class Loader {
 public:
  Result<ProfileSet, Diagnostics> run(const std::string& path);

 private:
  std::optional<RootKind> loadFile(const std::string& abs, const std::string& display, const Reference* from);
  std::optional<RootKind> parseRoot(Ctx& ctx, pugi::xml_node root, const std::string& abs);
  void follow(const Reference& ref);
  std::string cycleText(const std::string& abs) const;
  void sortByFileAndLine();

  ProfileSet set_;
  Diagnostics diags_;
  std::map<std::string, std::optional<RootKind>> kinds_;    // nullopt: could not be read
  std::map<std::string, std::size_t> file_order_;           // display path -> load order
  std::vector<std::pair<std::string, std::string>> stack_;  // (abs, display) being loaded
  bool cycle_ = false;
};

Result<ProfileSet, Diagnostics> Loader::run(const std::string& path) {
  set_.root = absolutePath(path);
  const std::string display = fs::path(path).lexically_normal().string();
  const auto kind = loadFile(set_.root, display, nullptr);
  if (kind) set_.root_kind = *kind;
  if (kind && !cycle_) validate(set_, diags_);
  if (!diags_.empty()) {
    sortByFileAndLine();
    return diags_;
  }
  return std::move(set_);
}

std::optional<RootKind> Loader::loadFile(const std::string& abs, const std::string& display, const Reference* from) {
  if (const auto it = kinds_.find(abs); it != kinds_.end()) return it->second;
  kinds_[abs] = std::nullopt;
  std::string open_error;
  Diagnostic syntax;
  const auto file = XmlFile::read(abs, display, open_error, syntax);
  if (!file && from != nullptr && from->optional) {  // OPRoS's engine never opened it either
    const std::string why = open_error.empty() ? syntax.str() : open_error;
    set_.warnings.push_back(
        Diagnostic{from->where, fmt::format("{}: cannot read '{}' ({}): nothing is checked against it", from->who,
                                            from->written, why)});
    return std::nullopt;
  }
  if (!file && !open_error.empty()) {
    if (from == nullptr) {
      diags_.push_back(Diagnostic{Where{display, 0}, "cannot open: " + open_error});
    } else {
      std::string elsewhere;
      for (const std::string& place : from->also_searched) elsewhere += (elsewhere.empty() ? "" : ", ") + place;
      if (!elsewhere.empty()) elsewhere = fmt::format(" (nor in OPRoS's layouts: {})", elsewhere);
      diags_.push_back(Diagnostic{from->where, fmt::format("{}: cannot open '{}': {}{}", from->who, from->written,
                                                           open_error, elsewhere)});
    }
    return std::nullopt;
  }
  if (!file) {
    diags_.push_back(std::move(syntax));
    return std::nullopt;
  }
  file_order_.emplace(display, file_order_.size());
  // A type profile's problems do not stop a run: OPRoS's engine never read those files. Each
  // is a warning, and nothing is checked against a type profile that has one.
  const bool optional = from != nullptr && from->optional;
  Diagnostics type_problems;
  Ctx ctx(*file, optional ? type_problems : diags_, set_.warnings);
  const auto kind = parseRoot(ctx, file->root(), abs);
  ctx.finish();
  if (!type_problems.empty()) {
    for (Diagnostic& d : type_problems)
      set_.warnings.push_back({d.where, d.message + " (nothing is checked against this file)"});
    set_.service_types.erase(abs);
    set_.data_types.erase(abs);
  }
  kinds_[abs] = kind;
  if (!kind) return std::nullopt;
  stack_.emplace_back(abs, display);
  for (const Reference& ref : ctx.references()) follow(ref);
  stack_.pop_back();
  return kind;
}

std::optional<RootKind> Loader::parseRoot(Ctx& ctx, pugi::xml_node root, const std::string& abs) {
  for (pugi::xml_node extra = root.next_sibling(); extra; extra = extra.next_sibling()) {
    if (extra.type() == pugi::node_element) {
      ctx.error(extra, fmt::format("second root element {} (a profile has one)", tag(extra)));
    }
  }
  const auto kind = rootKindOf(root.name());
  if (!kind) {
    ctx.error(root, fmt::format("unknown root element {} (expected {})", tag(root),
                                kindList({RootKind::Component, RootKind::Composite, RootKind::Package, RootKind::System,
                                          RootKind::Node, RootKind::ServiceType, RootKind::DataType,
                                          RootKind::EngineConfig})));
    return std::nullopt;
  }
  // The file's profile, keyed by its path, parsed by `parse`.
  auto into = [&](auto& profiles, auto parse) {
    auto& p = profiles[abs];
    p.file = abs;
    parse(ctx, root, p);
  };
  switch (*kind) {
    case RootKind::Component: into(set_.components, parseComponentProfile); break;
    case RootKind::Composite: into(set_.composites, parseCompositeProfile); break;
    case RootKind::Package: into(set_.packages, parsePackageProfile); break;
    case RootKind::ServiceType: into(set_.service_types, parseServiceTypeProfile); break;
    case RootKind::DataType: into(set_.data_types, parseDataTypeProfile); break;
    case RootKind::EngineConfig: parseEngineConfig(ctx, root); break;
    case RootKind::Node:  // and, to all that assembles components, the passive component it is
      into(set_.nodes, parseNodeProfile);
      set_.components[abs] = set_.nodes[abs].component;
      break;
    case RootKind::System: {
      SystemProfile s;
      s.file = abs;
      parseSystemProfile(ctx, root, s);
      if (!set_.system) set_.system = std::move(s);  // only a root can be a system profile
      break;
    }
  }
  return kind;
}

void Loader::follow(const Reference& ref) {
  const bool in_progress = std::any_of(stack_.begin(), stack_.end(),
                                       [&](const auto& e) { return e.first == ref.path; });
  const auto kind = in_progress ? kinds_[ref.path] : loadFile(ref.path, ref.display, &ref);
  if (!kind) return;
  const bool accepted = std::find(ref.accepted.begin(), ref.accepted.end(), *kind) != ref.accepted.end();
  if (!accepted) {
    Diagnostic d{ref.where, fmt::format("{}: '{}' is a <{}>, expected {}", ref.who, ref.written, name(*kind),
                                        kindList(ref.accepted))};
    if (ref.optional) set_.warnings.push_back(std::move(d));
    else diags_.push_back(std::move(d));
  } else if (in_progress) {
    cycle_ = true;
    diags_.push_back(Diagnostic{ref.where, fmt::format("{}: circular reference: {}", ref.who, cycleText(ref.path))});
  } else if (ref.declared && *ref.declared != *kind) {
    diags_.push_back(Diagnostic{ref.where, fmt::format("{} has <type> {} but '{}' is a <{}>", ref.who,
                                                       *ref.declared == RootKind::Component ? "atomic" : "composite",
                                                       ref.written, name(*kind))});
  }
}

/// Files in load order (the root first), each file's problems in line order.
void Loader::sortByFileAndLine() {
  auto rank = [&](const Diagnostic& d) {
    const auto it = file_order_.find(d.where.file);
    return std::pair{it == file_order_.end() ? file_order_.size() : it->second, d.where.line};
  };
  std::stable_sort(diags_.begin(), diags_.end(),
                   [&](const Diagnostic& a, const Diagnostic& b) { return rank(a) < rank(b); });
}

std::string Loader::cycleText(const std::string& abs) const {
  std::string out;
  bool in_cycle = false;
  for (const auto& [path, display] : stack_) {
    in_cycle = in_cycle || path == abs;
    if (in_cycle) out += display + " -> ";
  }
  for (const auto& [path, display] : stack_) {
    if (path == abs) return out + display;
  }
  return out;
}

}  // namespace
}  // namespace detail

Result<ProfileSet, Diagnostics> load(const std::string& path) {
  try {
    return detail::Loader().run(path);
  } catch (const std::exception& e) {  // bad_alloc and the like: still no throw out of load()
    return Diagnostics{Diagnostic{Where{path, 0}, fmt::format("internal error: {}", e.what())}};
  }
}

std::string rootElementName(const std::string& path) {
  pugi::xml_document doc;
  if (!doc.load_file(path.c_str())) return {};
  return doc.document_element().name();
}

}  // namespace keel::profile
