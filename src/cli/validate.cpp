// keel validate FILE.xml... [--load] [--strict]: exit 0, or `file:line: message` per problem and
// exit 2. What loads but has no effect is a `file:line: warning: message` (exit 0; with --strict
// a problem, `file:line: message (--strict)`).
// Profiles, and fault scenarios (checked as `keel run --inject` reads them, before a run).
// Without --load, each <validity field=".."> on a port of a message type keel ships is checked
// against the message's fields. With --load, libraries are also loaded — every instance's, whatever its <process> — and
// every port of code checked against its profile, and each connection between processes as the component processes
// check it when they connect (nothing is initialized or run); what loading warns of (an OPRoS component's code that
// disagrees with its profile) is printed as `keel run` prints it, and is a problem with --strict.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>

#include "cli/commands.hpp"
#include "dds/field_validity.hpp"
#include "dds/type_registry.hpp"
#include "engine/engine.hpp"
#include "injection/scenario.hpp"
#include "profile/loader.hpp"

namespace keel::cli {
namespace {

/// Without --load: each <validity field=".."> whose port's type is a message keel has without
/// loading anything (the shipped ones) names a numeric field of it, and so does each field a
/// connection carries; the others are checked by --load, which loads the libraries that have
/// them. Each problem printed; how many.
int fieldRuleProblems(const profile::ProfileSet& set) {
  int problems = 0;
  for (const auto& [path, component] : set.components)
    for (const auto& port : component.data_ports)
      if (auto r = dds::resolveFieldRules(port, "", true); !r) {
        std::cerr << r.error().message;
        problems += static_cast<int>(std::count(r.error().message.begin(), r.error().message.end(), '\n'));
      }
  // A connection carrying a field (<source field="..">) of a port whose message keel has.
  for (const auto& [path, package] : set.packages)
    for (const profile::Connection& c : package.connections) {
      if (c.source.field.empty()) continue;
      const auto sub = std::find_if(package.subcomponents.begin(), package.subcomponents.end(),
                                    [&](const profile::Subcomponent& s) { return s.name == c.source.component; });
      const auto component = sub == package.subcomponents.end() ? set.components.end()
                                                                : set.components.find(sub->reference);
      if (component == set.components.end()) continue;  // a composite's exported port: checked when keel runs
      const auto& ports = component->second.data_ports;
      const auto port = std::find_if(ports.begin(), ports.end(),
                                     [&](const auto& d) { return d.name == c.source.port; });
      const detail::DdsType* type = port == ports.end() ? nullptr : dds::findType(port->data_type);
      if (type == nullptr) continue;  // a user's message: checked by --load
      if (auto steps = runtime::resolveFieldTap(type->fields, type->ros_name, c.source.field); !steps) {
        std::cerr << fmt::format("{}: port_connection {}.{} field '{}' -> {}.{}: {}\n", c.where.str(),
                                 c.source.component, c.source.port, c.source.field, c.target.component, c.target.port,
                                 steps.error().message);
        ++problems;
      }
    }
  return problems;
}

struct ValidateOptions {
  std::vector<std::string> files;
  bool load = false;
  bool strict = false;
};

int validateFiles(const ValidateOptions& o) {
  int problems = 0;
  for (const auto& f : o.files) {
    if (profile::rootElementName(f) == "fault_scenario") {
      auto scenario = injection::loadScenario(f);
      if (!scenario) {
        for (const auto& d : scenario.error()) std::cerr << d.str() << '\n';
        problems += static_cast<int>(scenario.error().size());
      } else {
        int injections = 0;
        for (const auto& fault : scenario->faults) injections += fault.repeat;
        std::cout << f << ": ok (a fault scenario: " << injections << " injections)\n";
      }
      continue;
    }
    auto set = profile::load(f);
    if (!set) {
      for (const auto& d : set.error()) std::cerr << d.str() << '\n';
      problems += static_cast<int>(set.error().size());
      continue;
    }
    const std::size_t warnings = set->warnings.size();
    if (o.strict && warnings > 0) {
      for (const auto& w : set->warnings) std::cerr << w.str() << " (--strict)\n";
      problems += static_cast<int>(warnings);
      continue;
    }
    for (const auto& w : set->warnings) std::cerr << w.warningStr() << '\n';
    if (!o.load) {
      if (const int bad = fieldRuleProblems(*set); bad > 0) {
        problems += bad;
        continue;
      }
    }
    std::size_t load_warnings_seen = 0;
    bool runnable = set->root_kind == profile::RootKind::Package || set->root_kind == profile::RootKind::System ||
                    set->root_kind == profile::RootKind::Component;
    if (o.load && runnable) {
      // What loading finds and goes on without (an OPRoS component's code disagreeing with its
      // profile, a queue its code fixes): warnings, errors with --strict.
      std::vector<std::string> load_warnings;
      engine::EngineOptions eo;
      eo.check_only = true;  // every process's code, here: what keel run's processes would refuse
      eo.warn = [&load_warnings](const std::string& m) { load_warnings.push_back(m); };
      auto engine = engine::Engine::create(std::move(*set), eo);
      for (const auto& w : load_warnings) std::cerr << (o.strict ? w + " (--strict)" : "keel: warning: " + w) << '\n';
      if (o.strict) problems += static_cast<int>(load_warnings.size());
      if (!engine) {
        std::cerr << engine.error().message << '\n';
        ++problems;
        continue;
      }
      if (o.strict && !load_warnings.empty()) continue;
      load_warnings_seen = load_warnings.size();
    }
    if (warnings + load_warnings_seen == 0) std::cout << f << ": ok\n";
    else std::cout << f << ": ok, with " << warnings + load_warnings_seen << " warning(s)\n";
  }
  return problems == 0 ? 0 : 2;
}

}  // namespace

void addValidateCommand(CLI::App& app, std::function<int()>& run) {
  auto opts = std::make_shared<ValidateOptions>();
  CLI::App* cmd = app.add_subcommand("validate", "Check profiles (and what they reference) and fault scenarios");
  cmd->add_option("files", opts->files, "profiles and fault scenarios to check")->required();
  cmd->add_flag("--load", opts->load, "also load the libraries and check ports against code");
  cmd->add_flag("--strict", opts->strict,
                "make warnings errors: what a profile says and keel does not act on (OPRoS's vocabulary, "
                "docs/opros.md), settings without effect");
  cmd->callback([opts, &run] { run = [opts] { return validateFiles(*opts); }; });
}

}  // namespace keel::cli
