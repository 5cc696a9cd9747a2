// Engine: creating instances from the plan, checking their ports against their profiles, and
// connecting them. Every mismatch is an error naming the profile's file:line.
#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iterator>

#include "dds/field_validity.hpp"
#include "dds/type_registry.hpp"
#include "engine/engine.hpp"
#include "fault/fault_manager_component.hpp"
#include "runtime/field_rules.hpp"
#include "runtime/port_access.hpp"
#include "runtime/registry.hpp"

namespace keel::engine {
namespace {

struct ExpectedPort {
  std::string name;
  PortKind kind;
  PortDirection direction;
  std::string type;  // empty: not checked (service ports are checked by signature at connect)
  profile::Where where;
};

std::vector<ExpectedPort> expectedPorts(const profile::ComponentProfile& p) {
  std::vector<ExpectedPort> out;
  auto dir = [](PortDirection u) { return u == PortDirection::Input ? PortDirection::Input : PortDirection::Output; };
  for (const auto& d : p.data_ports) out.push_back({d.name, PortKind::Data, dir(d.usage), d.data_type, d.where});
  for (const auto& e : p.event_ports) out.push_back({e.name, PortKind::Event, dir(e.usage), e.data_type, e.where});
  for (const auto& s : p.service_ports)
    out.push_back({s.name, PortKind::Service,
                   s.usage == profile::ServiceUsage::Provided ? PortDirection::Input : PortDirection::Output, "",
                   s.where});
  return out;
}

std::string describe(PortKind k, PortDirection d) {
  if (k == PortKind::Service) return d == PortDirection::Input ? "provided service port" : "required service port";
  return fmt::format("{} {} port", d == PortDirection::Input ? "input" : "output", toString(k));
}

std::string_view policyName(QueuePolicy p) {
  switch (p) {
    case QueuePolicy::Fifo: return "fifo";
    case QueuePolicy::UFifo: return "ufifo";
    case QueuePolicy::Lifo: return "lifo";
    case QueuePolicy::Last: return "last";
  }
  return "fifo";
}

}  // namespace

void Engine::makeExecutionGates() {
  // OPRoS's execution order: a gate per instance in it, shared by its primary and replacements.
  auto gateOf = [this](const std::string& instance) -> runtime::ExecutionGate& {
    auto& gate = gates_[instance];
    if (!gate) gate = std::make_unique<runtime::ExecutionGate>();
    return *gate;
  };
  for (const auto& d : planned_.plan.execution_order) {
    runtime::ExecutionGate& source = gateOf(d.source);
    gateOf(d.target).addFollower(source, source.addTarget());
  }
  for (auto& [name, gate] : gates_) gate->freeze();
}

Result<void> Engine::instantiate() {
  makeExecutionGates();
  std::string errors;
  for (const auto& pi : planned_.plan.instances) {
    const profile::ComponentProfile& cp = *pi.profile;
    if (&cp == &plan::faultManagerProfile()) {
      Instance inst;
      inst.plan = &pi;
      inst.component = std::make_unique<fault::FaultManagerComponent>(fault_manager_);
      detail::ComponentCore& core = runtime::coreOf(*inst.component);
      core.instance_name = pi.name;
      core.class_name = cp.name;
      core.hooks = this;
      core.fault_sink = &fault_manager_;
      (void)configurePorts(inst);  // its one port has no validity: cannot fail
      inst.serving_slot->store(inst.component.get(), std::memory_order_release);
      instances_.push_back(std::move(inst));
      continue;
    }
    if (!isLocal(pi)) {
      Instance inst = makeStandIn(pi, errors);
      if (!inst.component) continue;  // runs in another component process
      inst.serving_slot->store(inst.component.get(), std::memory_order_release);
      instances_.push_back(std::move(inst));
      continue;
    }
    auto inst = makeInstance(pi);
    if (!inst) {
      errors += inst.error().message;
      continue;
    }
    inst->serving_slot->store(inst->component.get(), std::memory_order_release);
    instances_.push_back(std::move(*inst));
  }
  for (const auto& inst : instances_) by_name_.emplace(inst.plan->name, &inst);
  // A node's rules are checked once, by keel run (or keel validate): after the libraries above
  // are loaded, whose messages a node's ports may carry.
  if (options_.host == nullptr) {
    if (auto r = checkNodeFieldRules(); !r) errors += r.error().message + '\n';
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

Result<std::string> Engine::findLibrary(const profile::ComponentProfile& cp) const {
  Result<std::string> lib = loader_.resolve(cp.library_name, std::filesystem::path(cp.file).parent_path().string());
  if (!lib && runtime::Registry::instance().find(cp.name, "")) return std::string();  // linked into this program
  return lib;
}

// keel run: the proxy of a component in a process of its own, or of a node; none (no
// component) for an instance another component process runs. What its ports' rules refuse is
// added to `errors`.
Instance Engine::makeStandIn(const plan::PlannedInstance& pi, std::string& errors) {
  Instance inst;
  inst.component = side_->standIn(pi);
  if (!inst.component) return inst;
  inst.plan = &pi;
  detail::ComponentCore& core = runtime::coreOf(*inst.component);
  core.instance_name = pi.name;
  core.class_name = pi.profile->name;
  core.fault_sink = &fault_manager_;
  if (pi.node) {
    core.hooks = this;  // a node has no engine of its own: keel run logs its states
    // Its output ports, filled from its topics: their <validity> is checked on each value.
    if (auto r = configurePorts(inst); !r) errors += r.error().message + '\n';
  }
  return inst;
}

Result<Instance> Engine::makeInstance(const plan::PlannedInstance& pi) {
  const profile::ComponentProfile& cp = *pi.profile;
  Result<std::string> lib = findLibrary(cp);
  if (!lib)
    return fail(fmt::format("{}: component '{}' ({}): {}\n", cp.where.str(), pi.name, cp.name, lib.error().message));
  const std::string& library = *lib;
  auto created = library.empty() ? [&]() -> Result<std::unique_ptr<Component>> {
    return runtime::Registry::instance().find(cp.name, "")->factory();
  }()
      : loader_.create(cp.name, library);
  if (!created) return fail(fmt::format("{}: component '{}': {}\n", cp.where.str(), pi.name, created.error().message));
  Instance inst;
  inst.plan = &pi;
  inst.component = std::move(*created);
  detail::ComponentCore& core = runtime::coreOf(*inst.component);
  core.instance_name = pi.name;
  core.class_name = cp.name;
  core.hooks = this;
  core.fault_sink = &fault_manager_;
  core.profile_file = cp.file;
  side_->adopt(pi, core);
  for (const auto& [k, v] : pi.properties) core.properties[k] = v;
  if (pi.policy && pi.policy->deadline_ms) core.deadline_ns = static_cast<std::int64_t>(*pi.policy->deadline_ms * 1e6);
  if (const auto gate = gates_.find(pi.name); gate != gates_.end()) core.gate = gate->second.get();
  if (auto r = checkPorts(inst); !r) return r.error();
  if (pi.policy && pi.policy->heartbeat_timeout_ms)
    core.watch.heartbeat_ns = static_cast<std::int64_t>(*pi.policy->heartbeat_timeout_ms * 1e6);
  if (pi.policy && pi.policy->checkpoint_period_ms)
    core.checkpoints.period_ns = static_cast<std::int64_t>(*pi.policy->checkpoint_period_ms * 1e6);
  if (auto r = configurePorts(inst); !r) return r.error();
  return inst;
}

Result<void> Engine::configurePorts(Instance& inst) {
  const profile::ComponentProfile& cp = *inst.plan->profile;
  detail::ComponentCore& core = runtime::coreOf(*inst.component);
  std::string errors;
  for (const auto& d : cp.data_ports) {
    detail::PortBase* port = core.findPort(d.name);
    if (!port) continue;  // an OPRoS component without it: checkPorts warned
    if (d.usage == PortDirection::Input) configureQueue(inst, d, *static_cast<detail::InputPortBase*>(port));
    if (!d.field_validity.empty()) {
      if (auto r = configureFieldRules(inst, d, *port); !r) errors += r.error().message;
    }
    if (!d.validity) continue;
    if (!port->numeric()) {
      errors += fmt::format(
          "{}: component '{}': <validity> on port '{}' of type '{}': only numbers and "
          "arrays of numbers can be range-checked\n",
          d.validity->where.str(), inst.plan->name, d.name, port->typeName());
      continue;
    }
    rules_.push_back(std::make_unique<detail::ValidityRule>(detail::ValidityRule{d.validity->min, d.validity->max}));
    detail::PortAccess::setValidity(*port, rules_.back().get());
  }
  for (const auto& e : cp.event_ports) {
    if (e.usage != PortDirection::Input) continue;
    if (auto* port = static_cast<detail::InputPortBase*>(core.findPort(e.name)))
      port->configureQueue(QueuePolicy::Fifo, e.queue_size);
  }
  for (const auto& sp : cp.service_ports) {
    if (sp.usage != profile::ServiceUsage::Required) continue;
    if (auto* port = static_cast<detail::ServicePortBase*>(core.findPort(sp.name)))
      port->setTimeout(std::chrono::nanoseconds(static_cast<std::int64_t>(sp.timeout_ms * 1e6)));
  }
  if (!errors.empty()) return fail(errors);
  return {};
}

Result<void> Engine::configureFieldRules(const Instance& inst, const profile::DataPort& d, detail::PortBase& port) {
  // The port's own type, not the profile's data_type: the rules walk values of this C++ type.
  const detail::DdsType* type = dds::findType(port.typeName());
  if (type != nullptr && type->type != port.type()) type = nullptr;
  auto rules = dds::resolveFieldRules(type, port.typeName(), d, fmt::format("component '{}': ", inst.plan->name));
  if (!rules) return rules.error();
  field_rules_.push_back(std::make_unique<detail::FieldRules>(detail::FieldRules{std::move(*rules)}));
  detail::PortAccess::setFieldRules(port, field_rules_.back().get());
  return {};
}

Result<void> Engine::checkNodeFieldRules() const {
  std::string errors;
  for (const auto& pi : planned_.plan.instances) {
    if (pi.node == nullptr) continue;
    for (const auto& d : pi.profile->data_ports)
      if (auto r = dds::resolveFieldRules(d, fmt::format("node '{}': ", pi.name), false); !r)
        errors += r.error().message;
  }
  if (errors.empty()) return {};
  errors.pop_back();
  return fail(errors);
}

Result<detail::PortBase*> Engine::tapField(detail::PortBase& src, const std::string& field,
                                           detail::ConnectionBase& connection) {
  const detail::DdsType* type = dds::findType(src.typeName());
  if (type == nullptr || type->type != src.type())
    return fail(
        fmt::format("its type '{}' is not a ROS 2 message keel has (a keel::msg type: docs/messages.md), so "
                    "it has no fields",
                    src.typeName()));
  auto steps = runtime::resolveFieldTap(type->fields, type->ros_name, field);
  if (!steps) return steps.error();
  const detail::FieldRules* current = detail::PortAccess::fieldRules(src);
  auto rules = std::find_if(field_rules_.begin(), field_rules_.end(),
                            [&](const auto& r) { return r.get() == current; });
  if (current == nullptr || rules == field_rules_.end()) {
    field_rules_.push_back(std::make_unique<detail::FieldRules>());
    rules = std::prev(field_rules_.end());
  }
  auto out = std::make_unique<OutputDataPort<double>>(&src.owner(), src.name() + "." + field);
  if (!static_cast<detail::OutputPortBase&>(*out).attach(connection)) return fail("the target is not a 'double' input");
  (*rules)->taps.push_back({std::move(*steps), out.get()});
  detail::PortAccess::setFieldRules(src, rules->get());
  detail::PortBase* sends = out.get();
  taps_.push_back({&src.owner(), src.name(), field, std::move(out), &connection});
  return sends;
}

void Engine::configureQueue(const Instance& inst, const profile::DataPort& d, detail::InputPortBase& port) {
  const detail::ComponentCore& core = runtime::coreOf(*inst.component);
  const auto code = core.code_queues.find(d.name);
  if (code == core.code_queues.end()) {
    port.configureQueue(d.queue_policy, d.queue_size);
    return;
  }
  // An OPRoS component's code fixed this queue in the port's constructor: OPRoS's engine used
  // the code's and never the profile's, and the component was written against it.
  const auto [policy, size] = code->second;
  if (policy != d.queue_policy || size != d.queue_size)
    warn(
        fmt::format("{}: component '{}': port '{}': the profile asks for {} of {}, the code constructs {} of {}; "
                    "as in OPRoS, the code's queue is used",
                    d.where.str(), inst.plan->name, d.name, policyName(d.queue_policy), d.queue_size,
                    policyName(policy), size));
  port.configureQueue(policy, size);
}

Result<void> Engine::checkPorts(const Instance& inst) {
  const profile::ComponentProfile& cp = *inst.plan->profile;
  const detail::ComponentCore& core = runtime::coreOf(*inst.component);
  std::string errors;
  auto expected = expectedPorts(cp);
  for (const auto& e : expected) {
    detail::PortBase* p = core.findPort(e.name);
    if (!p) {
      errors += fmt::format("{}: component '{}': the profile declares {} '{}' but class '{}' has no such port\n",
                            e.where.str(), inst.plan->name, describe(e.kind, e.direction), e.name, cp.name);
    } else if (p->kind() != e.kind || p->direction() != e.direction) {
      errors += fmt::format("{}: component '{}': port '{}' is an {} in the profile but an {} in class '{}'\n",
                            e.where.str(), inst.plan->name, e.name, describe(e.kind, e.direction),
                            describe(p->kind(), p->direction()), cp.name);
    } else if (!e.type.empty() && canonicalTypeName(e.type) != canonicalTypeName(p->typeName())) {
      errors += fmt::format("{}: component '{}': port '{}' carries '{}' in the profile but '{}' in class '{}'\n",
                            e.where.str(), inst.plan->name, e.name, e.type, p->typeName(), cp.name);
    }
  }
  for (const detail::PortBase* p : core.ports) {
    bool declared = false;
    for (const auto& e : expected) declared |= e.name == p->name();
    // An OPRoS service port's keel type is the one every OPRoS method travels as: not worth naming.
    const std::string type = core.opros && p->kind() == PortKind::Service ? std::string()
                                                                          : fmt::format(" ({})", p->typeName());
    if (!declared)
      errors += fmt::format("{}: component '{}': class '{}' has {} '{}'{} that the profile does not declare\n",
                            cp.where.str(), inst.plan->name, cp.name, describe(p->kind(), p->direction()), p->name(),
                            type);
  }
  if (errors.empty()) return {};
  if (core.opros) {
    // OPRoS's engine never compared a component's code with its profile; a connection to a
    // port the code lacks is still an error (connect()).
    errors.pop_back();
    for (std::size_t start = 0; start <= errors.size();) {
      const std::size_t end = std::min(errors.find('\n', start), errors.size());
      warn(errors.substr(start, end - start) + " (an OPRoS component: it loads)");
      start = end + 1;
    }
    return {};
  }
  return fail(errors);
}

Result<void> Engine::connect() {
  auto port = [this](const profile::Endpoint& e) -> detail::PortBase* {
    Component* c = find(e.component);
    return c ? runtime::coreOf(*c).findPort(e.port) : nullptr;
  };
  std::string errors;
  const std::vector<std::size_t> crossing = supervision::crossingConnections(planned_.plan);
  for (std::size_t i = 0; i < planned_.plan.connections.size(); ++i) {
    const plan::PlannedConnection& pc = planned_.plan.connections[i];
    if (std::find(crossing.begin(), crossing.end(), i) != crossing.end()) {  // below
      if (!pc.source.field.empty())
        errors += fmt::format(
            "{}: port_connection {}.{} field '{}' -> {}.{}: a connection carrying a field joins "
            "ports of one process (one of these components runs in a <process> of its own)\n",
            pc.where.str(), pc.source.component, pc.source.port, pc.source.field, pc.target.component, pc.target.port);
      continue;
    }
    const plan::PlannedInstance* a = planned_.plan.find(pc.source.component);
    const plan::PlannedInstance* b = planned_.plan.find(pc.target.component);
    if (b && b->node) continue;  // a node's input: its topic, a <publish> of the source's (the plan's)
    // Both ends in another process (the plan keeps services in one); a node's output is its
    // stand-in's port, here.
    if (a && !isLocal(*a) && !a->node) continue;
    detail::PortBase* src = port(pc.source);
    detail::PortBase* dst = port(pc.target);
    if (!src || !dst) {
      errors += fmt::format("{}: port_connection {}.{} -> {}.{}: no such port\n", pc.where.str(), pc.source.component,
                            pc.source.port, pc.target.component, pc.target.port);
      continue;
    }
    if (!pc.source.field.empty()) {  // one number of each message: a port of the source's sends it
      std::unique_ptr<detail::ConnectionBase> conn;
      if (dst->kind() == PortKind::Data && dst->direction() == PortDirection::Input)
        conn = static_cast<detail::InputPortBase*>(dst)->makeConnection();
      Result<detail::PortBase*> tapped = conn ? tapField(*src, pc.source.field, *conn)
                                              : Result<detail::PortBase*>(fail("the target is not a data input"));
      if (tapped) {
        wires_.push_back({conn.get(), *tapped, dst});  // a replaced target is re-pointed as any
        connections_.push_back(std::move(conn));
      } else {
        errors += fmt::format("{}: port_connection {}.{} field '{}' -> {}.{}: {}\n", pc.where.str(),
                              pc.source.component, pc.source.port, pc.source.field, pc.target.component, pc.target.port,
                              tapped.error().message);
      }
      continue;
    }
    bool ok = false;
    if (src->kind() == PortKind::Service) {
      ok = static_cast<detail::ServicePortBase*>(src)->bind(*static_cast<detail::ServicePortBase*>(dst));
      if (ok) wires_.push_back({nullptr, src, dst});
    } else if (src->kind() == dst->kind() && dst->direction() == PortDirection::Input &&
               src->direction() == PortDirection::Output) {
      auto conn = static_cast<detail::InputPortBase*>(dst)->makeConnection();
      ok = static_cast<detail::OutputPortBase*>(src)->attach(*conn);
      if (ok) {
        wires_.push_back({conn.get(), src, dst});
        connections_.push_back(std::move(conn));
      }
    }
    if (!ok)
      errors += fmt::format("{}: port_connection {}.{} ({} {}) -> {}.{} ({} {}): types do not match\n", pc.where.str(),
                            pc.source.component, pc.source.port, toString(src->kind()), src->typeName(),
                            pc.target.component, pc.target.port, toString(dst->kind()), dst->typeName());
  }
  if (!crossing.empty()) {
    runtime::ipc::Session& session = side_->session();
    auto fds = side_->ringDescriptors();
    // A writer fenced by a takeover is a host that was declared dead: it leaves at once.
    auto fenced = [] { ::_exit(supervision::kExitFenced); };
    auto made = crossings_.connect(
        planned_.plan, side_->process(), session, std::move(fds), [this](std::string_view n) { return find(n); },
        options_.host_start_timeout, fenced, [this](const std::string& m) { warn(m); });
    if (!made) errors += made.error().message + '\n';
    for (const runtime::Wire& w : crossings_.wires()) wires_.push_back(w);
  }
  // DDS topics (<dds>): the bindings of this process's components, made here, in the process
  // whose threads run them (decision 0019); keel run makes those of its own.
  std::vector<plan::PlannedDds> dds;
  for (const plan::PlannedDds& d : planned_.plan.dds)
    if (const plan::PlannedInstance* pi = planned_.plan.find(d.binding.endpoint.component); pi && isLocal(*pi)) {
      dds.push_back(d);
      dds.back().redundancy = pi->redundancy;
    }
  const bool diagnostics = side_->publishesDiagnostics();
  // keel run joins DDS for its own topics, /diagnostics and its nodes, not for the topics of
  // components in processes of their own, whose hosts hold them (decision 0019).
  const bool graph = side_->joinsRosGraph() && (!dds.empty() || diagnostics || planned_.plan.hasNodes());
  if (!dds.empty() || diagnostics || graph)
    dds_ = std::make_unique<dds::DdsPorts>(*this, [this](const std::string& m) { warn(m); });
  if (!dds.empty()) {
    // A standby's endpoints are made now, so that its peers have matched them when it takes
    // over; its readers stand by until then (takeRoleAsHost).
    const auto readers = side_->standingBy() ? dds::DdsPorts::Readers::StandingBy : dds::DdsPorts::Readers::Serving;
    if (auto made = dds_->open(dds, port, readers); !made) errors += made.error().message + '\n';
    for (const runtime::Wire& w : dds_->wires()) wires_.push_back(w);
  }
  if (diagnostics) {
    if (auto made = dds_->publishDiagnostics(*planned_.plan.diagnostics_domain, [this] { return health(); }); !made)
      errors += made.error().message + '\n';
    fault_manager_.onChange([this] { dds_->pokeDiagnostics(); });  // a fault, its actions, its recovery
  }
  if (dds::GraphWatch* watch = graph ? side_->graphWatch() : nullptr) {  // the nodes keel runs or attaches to
    std::vector<dds::WatchedNode> nodes;
    for (const plan::PlannedInstance& pi : planned_.plan.instances) {
      if (!pi.node) continue;
      dds::WatchedNode& w = nodes.emplace_back(
          dds::WatchedNode{pi.name, pi.node->fullName(), {}, pi.node->diagnostics_name, plan::standbyNodeNames(pi)});
      for (const profile::NodeTopic& t : pi.node->topics)
        for (const profile::DataPort& d : pi.node->component.data_ports)
          if (d.name == t.port && d.usage == PortDirection::Output) w.outputs.push_back(t.topic);
    }
    if (auto watching = dds_->watchNodes(planned_.plan.rosDomain(), std::move(nodes), *watch); !watching)
      errors += watching.error().message + '\n';
    // Their output topics, into their stand-ins' output ports.
    std::vector<dds::DdsPorts::NodeOutput> outputs;
    for (const plan::PlannedInstance& pi : planned_.plan.instances) {
      if (!pi.node) continue;
      for (const profile::NodeTopic& t : pi.node->topics) {
        detail::PortBase* p = port({pi.name, t.port});
        if (p == nullptr || p->direction() != PortDirection::Output) continue;
        profile::DdsBinding b;
        b.publish = false;
        b.endpoint = {pi.name, t.port};
        b.topic = t.topic;
        b.type = p->typeName();
        for (const profile::DataPort& d : pi.node->component.data_ports)
          if (d.name == t.port) b.type = d.data_type;
        b.qos = t.qos;
        b.depth = t.depth;
        b.deadline_ms = t.deadline_ms;
        b.liveliness_ms = t.liveliness_ms;
        b.where = t.where;
        outputs.push_back({pi.name, std::move(b), p});
      }
    }
    if (auto reading = dds_->readNodeOutputs(planned_.plan.rosDomain(), outputs); !reading)
      errors += reading.error().message + '\n';
    // Their safe commands, written while an emergency stop holds (RunSide); a role with an
    // alternative node has both nodes' (the actuators behind them are the same), each topic once.
    std::vector<dds::NodeSafeCommand> safe;
    for (const plan::PlannedInstance& pi : planned_.plan.instances) {
      if (!pi.node) continue;
      for (const profile::NodeProfile* p : {pi.node, alternativeNode(pi)}) {
        if (p == nullptr || !p->emergency) continue;
        for (const profile::SafeCommand& c : p->emergency->publish)
          if (std::none_of(safe.begin(), safe.end(), [&](const dds::NodeSafeCommand& s) {
                return s.instance == pi.name && s.command.topic == c.topic;
              }))
            safe.push_back({pi.name, c});
      }
    }
    if (auto opened = dds_->openSafeCommands(planned_.plan.rosDomain(), safe); !opened)
      errors += opened.error().message + '\n';
  }
  if (dds::LifecycleWatch* lifecycles = graph ? side_->lifecycleWatch() : nullptr) {  // the managed nodes keel drives
    std::vector<dds::LifecycleNode> nodes;
    for (const plan::PlannedInstance& pi : planned_.plan.instances)
      if (pi.node && !pi.attached && pi.node->lifecycle) {
        std::vector<std::string> names{pi.node->fullName()};  // and its standbys'
        for (std::string& s : plan::standbyNodeNames(pi)) names.push_back(std::move(s));
        nodes.push_back({pi.name, std::move(names)});
      }
    if (!nodes.empty()) {
      if (auto watching = dds_->watchLifecycles(planned_.plan.rosDomain(), nodes, *lifecycles); !watching)
        errors += watching.error().message + '\n';
      else side_->lifecyclesReachable();
    }
  }
  if (dds::ParameterWatch* params = graph ? side_->parameterWatch() : nullptr) {  // the nodes keel restarts
    std::vector<dds::WatchedNode> nodes;
    for (const plan::PlannedInstance& pi : planned_.plan.instances)
      if (pi.node && !pi.attached) nodes.push_back({pi.name, pi.node->fullName(), {}, {}, plan::standbyNodeNames(pi)});
    if (!nodes.empty())
      if (auto watching = dds_->watchParameters(planned_.plan.rosDomain(), std::move(nodes), *params); !watching)
        errors += watching.error().message + '\n';
  }
  if (graph) {  // last: it lists the writers and readers made above
    if (auto joined = dds_->joinGraph(planned_.plan.rosDomain(), planned_.plan.name); !joined)
      errors += joined.error().message + '\n';
  }
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

}  // namespace keel::engine
