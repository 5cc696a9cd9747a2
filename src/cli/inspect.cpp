// keel inspect LIB.so: the components a library registers, with their ports (kind, direction,
// data type) and, where a component profile for the class is found next to the library or in
// --profiles DIR, its properties and execution semantics.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>

#include "cli/commands.hpp"
#include "profile/loader.hpp"
#include "runtime/component_core.hpp"
#include "runtime/loader.hpp"

namespace fs = std::filesystem;

namespace keel::cli {
namespace {

struct InspectOptions {
  std::string library;
  std::vector<std::string> profile_dirs;
};

std::string direction(const detail::PortBase& p) {
  if (p.kind() == PortKind::Service) return p.direction() == PortDirection::Input ? "provided" : "required";
  return p.direction() == PortDirection::Input ? "input" : "output";
}

/// Component profiles in `dirs` whose class is `name` (best effort: unreadable files skipped).
std::vector<profile::ComponentProfile> profilesFor(const std::string& name, const std::vector<std::string>& dirs) {
  std::vector<profile::ComponentProfile> out;
  for (const auto& d : dirs) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(d, ec)) {
      if (e.path().extension() != ".xml") continue;
      auto set = profile::load(e.path().string());
      if (!set || set->root_kind != profile::RootKind::Component) continue;
      for (auto& [file, cp] : set->components)
        if (cp.name == name) out.push_back(cp);
    }
  }
  return out;
}

std::string showValue(const PropertyValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::vector<double>>) return fmt::format("{}", fmt::join(x, " "));
        else return fmt::format("{}", x);
      },
      v);
}

int inspect(const InspectOptions& o) {
  std::error_code ec;
  fs::path lib = fs::canonical(o.library, ec);
  if (ec) {
    std::cerr << o.library << ": " << ec.message() << '\n';
    return 1;
  }
  runtime::Loader loader(std::vector<std::string>{});
  auto loaded = loader.load(lib.string());
  if (!loaded) {
    std::cerr << loaded.error().message << '\n';
    return 1;
  }
  std::vector<std::string> dirs = o.profile_dirs;
  if (dirs.empty()) dirs = {lib.parent_path().string()};
  std::vector<std::string> names = (*loaded)->components;
  if ((*loaded)->opros_get) {
    // OPRoS's convention: one component per library, made by its getComponent(); listed under
    // the library's own name, which is how OPRoS's profiles name both.
    std::string stem = lib.stem().string();
    if (stem.rfind("lib", 0) == 0) stem.erase(0, 3);
    names.push_back(stem);
    fmt::print("{}: an OPRoS component library (getComponent)\n", lib.string());
  } else {
    fmt::print("{}: {} component(s)\n", lib.string(), names.size());
  }
  for (const auto& name : names) {
    auto c = loader.create(name, lib.string());
    fmt::print("\n{}\n", name);
    if (!c) {
      fmt::print("  cannot construct: {}\n", c.error().message);
      continue;
    }
    fmt::print("  ports:\n");
    for (const detail::PortBase* p : runtime::coreOf(**c).ports)
      fmt::print("    {:<20} {:<7} {:<8} {}\n", p->name(), toString(p->kind()), direction(*p), p->typeName());
    for (const auto& cp : profilesFor(name, dirs)) {
      fmt::print("  profile {}:\n", cp.file);
      const auto& e = cp.execution;
      fmt::print("    execution: {} period {} ms priority {}\n",
                 e.type == profile::ExecutionType::Periodic    ? "periodic"
                 : e.type == profile::ExecutionType::Aperiodic ? "aperiodic"
                                                               : "passive",
                 e.period_ms, e.priority);
      for (const auto& p : cp.properties)
        fmt::print("    property {:<16} {:<8} = {}\n", p.name, p.type, showValue(p.value));
    }
  }
  return 0;
}

}  // namespace

void addInspectCommand(CLI::App& app, std::function<int()>& run) {
  auto opts = std::make_shared<InspectOptions>();
  CLI::App* cmd = app.add_subcommand("inspect", "List the components, ports and properties a library provides");
  cmd->add_option("library", opts->library, "a component library (.so)")->required();
  cmd->add_option("--profiles", opts->profile_dirs,
                  "directories with component profiles (default: the library's directory)");
  cmd->callback([opts, &run] { run = [opts] { return inspect(*opts); }; });
}

}  // namespace keel::cli
