#include "plan/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "plan/fault_manager_profile.hpp"

namespace keel::plan {
namespace {

using profile::Endpoint;
using profile::ProfileSet;

// (instance, exported port) -> inner endpoint, for every composite instance.
using ExportMap = std::map<std::pair<std::string, std::string>, Endpoint>;

class Planner {
 public:
  explicit Planner(const ProfileSet& set) : set_(set) {}

  Result<void> addPackage(const std::string& prefix, const std::string& app,
                          const std::vector<profile::Subcomponent>& subs,
                          const std::vector<profile::Connection>& connections) {
    for (const auto& sub : subs)
      if (auto r = addSubcomponent(prefix, app, sub); !r) return r;
    addConnections(prefix, connections);
    return {};
  }

  /// Connections whose endpoints are `prefix` + a name added before (a system's: prefix "").
  void addConnections(const std::string& prefix, const std::vector<profile::Connection>& connections) {
    for (const auto& c : connections) {
      plan_.connections.push_back({c.port_type, resolve(prefix, c.source), resolve(prefix, c.target), c.where});
    }
  }

  void addDds(const std::string& prefix, const std::optional<profile::DdsSpec>& dds) {
    if (!dds) return;
    for (const auto& b : dds->bindings) {
      PlannedDds d{b, dds->domain.value_or(0), std::nullopt};
      d.binding.endpoint = resolve(prefix, b.endpoint);
      if (const PlannedInstance* pi = plan_.find(d.binding.endpoint.component); pi && pi->node) {
        plan_errors_ += fmt::format(
            "{}:{}: <{}> of {}.{}: '{}' is a ROS 2 node, whose ports are its own topics already (<topic> "
            "in its node profile); connect a component to it instead\n",
            b.where.file, b.where.line, b.publish ? "publish" : "subscribe", b.endpoint.component, b.endpoint.port,
            b.endpoint.component);
        continue;
      }
      plan_.dds.push_back(std::move(d));
    }
  }

  /// A connection to a ROS 2 node's input port is a DDS topic between them: the source's values
  /// are published on the node's <topic> for that port, with its QoS, in the ROS 2 domain, by
  /// the process that runs the source (as a <publish> of it would be); from another node's output
  /// on another topic, keel carries it over.
  void writeNodeInputs() {
    const int domain = plan_.rosDomain();
    for (const PlannedConnection& c : plan_.connections) {
      const PlannedInstance* node = plan_.find(c.target.component);
      if (node == nullptr || node->node == nullptr || c.type != PortKind::Data) continue;
      const profile::NodeProfile& np = *node->node;
      const auto t = std::find_if(np.topics.begin(), np.topics.end(),
                                  [&](const profile::NodeTopic& x) { return x.port == c.target.port; });
      const auto d = std::find_if(np.component.data_ports.begin(), np.component.data_ports.end(),
                                  [&](const profile::DataPort& x) { return x.name == c.target.port; });
      if (t == np.topics.end() || d == np.component.data_ports.end() || d->usage != PortDirection::Input) continue;
      // From another node's output on the same topic: the two nodes talk directly already.
      if (const PlannedInstance* from = plan_.find(c.source.component); from != nullptr && from->node != nullptr) {
        const auto& ft = from->node->topics;
        if (std::any_of(ft.begin(), ft.end(),
                        [&](const auto& x) { return x.port == c.source.port && x.topic == t->topic; }))
          continue;
      }
      profile::DdsBinding b;
      b.publish = true;
      b.endpoint = c.source;
      b.topic = t->topic;
      b.type = d->data_type;
      b.qos = t->qos;
      b.depth = t->depth;
      b.where = c.where;
      plan_.dds.push_back({std::move(b), domain, std::nullopt});
    }
  }

  void addDiagnostics(const std::optional<profile::DdsSpec>& dds) {
    if (dds && dds->diagnostics) plan_.diagnostics_domain = dds->domain.value_or(0);
  }

  void addTasks(const std::string& prefix, const std::vector<profile::Task>& tasks) {
    for (const auto& t : tasks) {
      PlannedExecutor ex{prefix + t.name, true, t.period_ms, t.priority, t.policy, {}, t.where};
      for (const auto& m : t.members) {
        for (const auto& inst : membersOf(prefix + m)) {
          ex.members.push_back(inst);
          in_task_.insert(inst);
          const PlannedInstance* planned = plan_.find(inst);
          if (planned && planned->profile->execution.sharing == profile::Sharing::Exclusive)
            plan_errors_ += fmt::format(
                "{}:{}: task '{}' names '{}', whose component '{}' is periodic-exclusive (a thread of its own, as "
                "OPRoS runs it): take it out of the task, or make it periodic\n",
                t.where.file, t.where.line, ex.name, inst, planned->profile->name);
        }
      }
      plan_.executors.push_back(std::move(ex));
    }
  }

  void addCoordination(const std::string& prefix, const profile::Coordination& c) {
    for (const auto& d : c.needs) plan_.depends.push_back({prefix + d.source, prefix + d.target, d.where});
    for (const auto& d : c.depends) {
      // An edge to a composite orders against each of its members.
      for (const auto& source : membersOf(prefix + d.source))
        for (const auto& target : membersOf(prefix + d.target))
          plan_.execution_order.push_back({source, target, d.where});
    }
  }

  Result<Plan> finish(std::string name) {
    addFaultManagerIfConnected();
    writeNodeInputs();
    std::map<std::tuple<double, int, std::string>, std::size_t> shared;  // (period, priority, process) -> executor
    for (const auto& inst : plan_.instances) {
      const auto& e = inst.profile->execution;
      if (in_task_.count(inst.name) || e.type == profile::ExecutionType::Passive) continue;
      if (e.sharing == profile::Sharing::Shared && e.type == profile::ExecutionType::Periodic) {
        // OPRoS's periodic-shared: one executor per period and priority, its members in load
        // order, scheduled as its first member says (docs/opros.md#what-means-what).
        const auto [it, fresh] = shared.try_emplace({e.period_ms, e.priority, inst.process}, plan_.executors.size());
        if (fresh) {
          std::string ex = fmt::format("periodic-shared-{:g}ms-p{}", e.period_ms, e.priority);
          if (!inst.process.empty()) ex += "-" + inst.process;
          plan_.executors.push_back({ex, true, e.period_ms, e.priority, e.policy, {}, inst.where});
        }
        plan_.executors[it->second].members.push_back(inst.name);
        continue;
      }
      plan_.executors.push_back({inst.name,
                                 e.type == profile::ExecutionType::Periodic,
                                 e.period_ms,
                                 e.priority,
                                 e.policy,
                                 {inst.name},
                                 inst.where});
    }
    plan_.name = std::move(name);
    if (auto r = groupProcesses(); !r) return r.error();
    return std::move(plan_);
  }

  void addFaultManagerIfConnected() {
    for (const auto& c : plan_.connections) {
      if (c.target.component != kFaultManagerInstance) continue;
      PlannedInstance inst;
      inst.name = kFaultManagerInstance;
      inst.profile = &faultManagerProfile();
      inst.where = c.where;
      plan_.instances.push_back(std::move(inst));
      return;
    }
  }

  // The processes and what may not cross between them: an executor runs in one process, and a
  // service call is a function call (a port of data or events crosses through shared memory).
  Result<void> groupProcesses() {
    std::string errors;
    for (const auto& [name, spec] : process_specs_) {
      (void)name;
      PlannedProcess p{spec.name, spec.standby, {}, spec.where};
      for (const auto& inst : plan_.instances)
        if (inst.process == spec.name) p.members.push_back(inst.name);
      plan_.processes.push_back(std::move(p));
    }
    std::sort(plan_.processes.begin(), plan_.processes.end(), [](const auto& a, const auto& b) {
      return std::tie(a.where.file, a.where.line) < std::tie(b.where.file, b.where.line);
    });
    auto processOf = [this](const std::string& instance) { return plan_.processOf(instance); };
    const auto& where = describeProcess;
    for (const auto& ex : plan_.executors) {
      for (const auto& m : ex.members) {
        if (processOf(m) == processOf(ex.members.front())) continue;
        errors += fmt::format("{}: task '{}' runs '{}' ({}) and '{}' ({}): a task's members run in one process\n",
                              ex.where.str(), ex.name, ex.members.front(), where(processOf(ex.members.front())), m,
                              where(processOf(m)));
        break;
      }
    }
    for (const auto& c : plan_.connections) {
      if (c.type != PortKind::Service) continue;
      const std::string a = processOf(c.source.component), b = processOf(c.target.component);
      if (a == b) continue;
      errors += fmt::format(
          "{}: port_connection {}.{} -> {}.{}: a service call cannot cross processes ('{}' runs in {}, '{}' in "
          "{}); put both in one <process>, or connect them by data or event ports\n",
          c.where.str(), c.source.component, c.source.port, c.target.component, c.target.port, c.source.component,
          where(a), c.target.component, where(b));
    }
    for (const auto& d : plan_.execution_order) {
      const std::string a = processOf(d.source), b = processOf(d.target);
      if (a.empty() && b.empty()) continue;
      errors += fmt::format(
          "{}: depends {} -> {}: OPRoS's execution order is kept within keel run's own process "
          "('{}' runs in {}, '{}' in {})\n",
          d.where.str(), d.source, d.target, d.source, where(a), d.target, where(b));
    }
    errors += plan_errors_;
    if (!errors.empty()) {
      errors.pop_back();
      return fail(errors);
    }
    return {};
  }

  // Records `spec` (qualified by `prefix`) as the process of `instance`, checking it says what
  // earlier mentions of the same process said.
  std::string noteProcess(const std::string& prefix, const profile::ProcessSpec& spec) {
    profile::ProcessSpec q = spec;
    q.name = prefix + spec.name;
    auto [it, inserted] = process_specs_.emplace(q.name, q);
    if (!inserted && it->second.standby != q.standby)
      plan_errors_ += fmt::format("{}:{}: process '{}' has standby=\"{}\" here but \"{}\" at {}:{}\n", q.where.file,
                                  q.where.line, q.name, q.standby, it->second.standby, it->second.where.file,
                                  it->second.where.line);
    return q.name;
  }

  Result<void> addComponentRoot(const profile::ComponentProfile& cp, const profile::NodeProfile* node = nullptr) {
    PlannedInstance inst;
    inst.name = cp.name;
    inst.profile = &cp;
    inst.node = node;
    for (const auto& p : cp.properties) {
      inst.properties[p.name] = p.value;
      inst.property_where[p.name] = p.where;
    }
    inst.where = cp.where;
    plan_.instances.push_back(std::move(inst));
    return {};
  }

 private:
  Result<void> addSubcomponent(const std::string& prefix, const std::string& app, const profile::Subcomponent& sub) {
    const std::string name = prefix + sub.name;
    if (auto it = set_.components.find(sub.reference); it != set_.components.end()) {
      PlannedInstance inst;
      inst.name = name;
      inst.profile = &it->second;
      for (const auto& p : it->second.properties) {
        inst.properties[p.name] = p.value;
        inst.property_where[p.name] = p.where;
      }
      for (const auto& [k, p] : sub.property_overrides) {
        inst.properties[k] = p.value;
        inst.property_where[k] = p.where;
      }
      inst.policy = sub.fault_policy;
      inst.application = app;
      inst.redundancy = sub.redundancy;
      if (auto node = set_.nodes.find(sub.reference); node != set_.nodes.end()) {
        inst.node = &node->second;
        inst.attached = sub.attach.has_value();
        if (sub.process && sub.process->standby == 0)
          plan_errors_ += fmt::format(
              "{}:{}: <process> of subcomponent '{}': a ROS 2 node is a process of its own (standby=\"N\" keeps N "
              "more of a lifecycle node ready)\n",
              sub.process->where.file, sub.process->where.line, sub.name);
        else if (sub.process && !node->second.lifecycle)
          plan_errors_ += fmt::format(
              "{}:{}: <process standby=\"{}\"> of subcomponent '{}': a standby node waits configured and inactive, "
              "which only a lifecycle node can: its profile ({}) has no <lifecycle/>\n",
              sub.process->where.file, sub.process->where.line, sub.process->standby, sub.name, node->second.file);
        else if (sub.process) inst.node_standby = sub.process->standby;
      } else if (sub.process) {
        inst.process = noteProcess(prefix, *sub.process);
      }
      inst.where = sub.where;
      plan_.instances.push_back(std::move(inst));
      members_[name] = {name};
      return {};
    }
    auto cit = set_.composites.find(sub.reference);
    if (cit == set_.composites.end())
      return fail(fmt::format("{}:{}: subcomponent '{}': '{}' is not a loaded component or composite", sub.where.file,
                              sub.where.line, sub.name, sub.reference));
    if (sub.redundancy)
      return fail(
          fmt::format("{}:{}: <redundancy> of subcomponent '{}': '{}' is a composite; give the role to the "
                      "components inside it whose topics it is about",
                      sub.redundancy->where.file, sub.redundancy->where.line, sub.name, sub.reference));
    const profile::CompositeProfile& comp = cit->second;
    std::size_t first = plan_.instances.size();
    const std::size_t composite = plan_.composites.size();
    plan_.composites.push_back({name, {}, sub.where});  // before its inner ones
    if (auto r = addPackage(name + ".", app, comp.subcomponents, comp.connections); !r) return r;
    std::vector<std::string> inner;
    const std::string process = sub.process ? noteProcess(prefix, *sub.process) : std::string();
    for (std::size_t i = first; i < plan_.instances.size(); ++i) {
      if (!plan_.instances[i].policy) plan_.instances[i].policy = sub.fault_policy;
      if (plan_.instances[i].process.empty()) plan_.instances[i].process = process;
      inner.push_back(plan_.instances[i].name);
    }
    plan_.composites[composite].members = inner;
    members_[name] = inner;
    for (const auto& e : comp.exported_ports) exports_[{name, e.name}] = resolve(name + ".", e.inner);
    addCoordination(name + ".", comp.coordination);
    return {};
  }

  Endpoint resolve(const std::string& prefix, const Endpoint& e) const {
    if (e.component == kFaultManagerInstance) return e;  // one per run, never prefixed
    Endpoint out{prefix + e.component, e.port};
    for (auto it = exports_.find({out.component, out.port}); it != exports_.end();
         it = exports_.find({out.component, out.port}))
      out = it->second;
    out.field = e.field;  // the connection's, whichever port it reaches
    return out;
  }

  std::vector<std::string> membersOf(const std::string& name) const {
    auto it = members_.find(name);
    return it == members_.end() ? std::vector<std::string>{name} : it->second;
  }

  const ProfileSet& set_;
  Plan plan_;
  ExportMap exports_;
  std::map<std::string, std::vector<std::string>> members_;
  std::set<std::string> in_task_;
  std::map<std::string, profile::ProcessSpec> process_specs_;  // by qualified name
  std::string plan_errors_;
};

}  // namespace

std::vector<std::string> standbyNodeNames(const PlannedInstance& instance) {
  std::vector<std::string> names;
  if (instance.node == nullptr || instance.node_standby == 0) return names;
  for (int k = 1; k <= instance.node_standby + 1; ++k)
    names.push_back(instance.node->inNamespace(instance.node->standbyName(k)));
  return names;
}

const PlannedInstance* Plan::find(std::string_view instance) const {
  for (const auto& i : instances)
    if (i.name == instance) return &i;
  return nullptr;
}

bool Plan::hasNodes() const {
  return std::any_of(instances.begin(), instances.end(), [](const PlannedInstance& pi) { return pi.node != nullptr; });
}

std::string Plan::processOf(std::string_view instance) const {
  const PlannedInstance* i = find(instance);
  return i ? i->process : std::string();
}

std::string describeProcess(const std::string& process) {
  return process.empty() ? std::string("keel run's own process") : "process '" + process + "'";
}

Result<Plan> makePlan(const ProfileSet& set) {
  Planner planner(set);
  switch (set.root_kind) {
    case profile::RootKind::Package: {
      const auto& pkg = set.packages.at(set.root);
      if (auto r = planner.addPackage("", "", pkg.subcomponents, pkg.connections); !r) return r.error();
      planner.addTasks("", pkg.tasks);
      planner.addCoordination("", pkg.coordination);
      planner.addDds("", pkg.dds);
      planner.addDiagnostics(pkg.dds);
      return planner.finish(pkg.name);
    }
    case profile::RootKind::System: {
      for (const auto& app : set.system->applications) {
        const auto& pkg = set.packages.at(app.reference);
        const std::string prefix = app.name + ".";
        if (auto r = planner.addPackage(prefix, app.name, pkg.subcomponents, pkg.connections); !r) return r.error();
        planner.addTasks(prefix, pkg.tasks);
        planner.addCoordination(prefix, pkg.coordination);
        planner.addDds(prefix, pkg.dds);
      }
      planner.addConnections("", set.system->connections);  // "app.instance" already
      planner.addDds("", set.system->dds);
      planner.addDiagnostics(set.system->dds);
      return planner.finish(set.system->name);
    }
    case profile::RootKind::Component: {
      const auto& cp = set.components.at(set.root);
      if (auto r = planner.addComponentRoot(cp); !r) return r.error();
      return planner.finish(cp.name);
    }
    case profile::RootKind::Node: {  // one node run alone, under the default fault policy
      const auto& cp = set.components.at(set.root);
      if (auto r = planner.addComponentRoot(cp, &set.nodes.at(set.root)); !r) return r.error();
      return planner.finish(cp.name);
    }
    case profile::RootKind::Composite: {
      const auto& comp = set.composites.at(set.root);
      if (auto r = planner.addPackage("", "", comp.subcomponents, comp.connections); !r) return r.error();
      planner.addCoordination("", comp.coordination);
      return planner.finish(comp.name);
    }
    case profile::RootKind::ServiceType:
    case profile::RootKind::DataType:
    case profile::RootKind::EngineConfig:
      return fail(
          fmt::format("{}: an OPRoS service type, data type or engine configuration, not components: "
                      "nothing to run",
                      set.root));
  }
  return fail("unknown profile kind");
}

Result<PlannedProfiles> planProfiles(ProfileSet set) {
  PlannedProfiles out;
  out.profiles = std::make_unique<const ProfileSet>(std::move(set));
  auto plan = makePlan(*out.profiles);
  if (!plan) return plan.error();
  out.plan = std::move(*plan);
  return out;
}

}  // namespace keel::plan
