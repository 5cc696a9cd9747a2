// Component's out-of-line members and the small detail:: functions the public headers call.
#include <cxxabi.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <memory>

#include "keel/component.hpp"
#include "keel/run_control.hpp"
#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/invoke.hpp"

namespace keel {

Component::Component() : core_(std::make_unique<detail::ComponentCore>()) {}
Component::~Component() = default;

const std::string& Component::instanceName() const { return core_->instance_name; }
State Component::state() const { return core_->state.load(std::memory_order_acquire); }
bool Component::emergencyLatched() const { return core_->fault.emergency.load(std::memory_order_acquire); }

const PropertyValue* Component::findProperty(std::string_view name) const {
  auto it = core_->properties.find(name);
  return it == core_->properties.end() ? nullptr : &it->second;
}

void Component::critical(void* addr, std::size_t len) {
  if (addr == nullptr || len == 0) return;
  auto& regions = core_->critical;
  auto same = [addr](const runtime::CriticalRegion& r) { return r.addr == addr; };
  if (auto it = std::find_if(regions.begin(), regions.end(), same); it != regions.end()) {
    it->len = len;  // registering again (e.g. onInitialize after a reset) updates the size
    return;
  }
  regions.push_back({addr, len});
}

void Component::raiseFault(std::string_view why) {
  if (core_->fault_sink) core_->fault_sink->report(*this, FaultEvent(FaultKind::User, core_->instance_name, why));
}

void Component::reportFault(const FaultEvent& fault) {
  if (core_->fault_sink) core_->fault_sink->report(*this, fault);
}

void Component::rejectProperty(std::string_view name, std::string_view why) const {
  detail::throwPropertyError(core_->instance_name, name, why);
}

void RunControl::endRun(std::string_view summary, std::string_view event, std::string_view fields_json) {
  auto* self = dynamic_cast<Component*>(this);
  if (!self) return;
  detail::ComponentCore& core = runtime::coreOf(*self);
  if (core.hooks) core.hooks->endRun(*self, summary, event, fields_json);
}

}  // namespace keel

namespace keel::detail {

void registerPort(Component* owner, PortBase* port) { ComponentAccess::core(*owner).ports.push_back(port); }

void notifyInput(Component& owner, bool is_event) {
  ComponentCore& core = ComponentAccess::core(owner);
  (is_event ? core.event_pending : core.input_pending).store(true, std::memory_order_release);
  if (runtime::Executor* ex = core.executor.load(std::memory_order_acquire)) ex->wake();
  else if (is_event) runtime::dispatchEventsPassive(owner);
}

void throwPropertyError(std::string_view component, std::string_view name, std::string_view why) {
  throw PropertyError(fmt::format("component '{}': property '{}' {}", component, name, why), std::string(name));
}

std::string demangle(const char* mangled) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> out(abi::__cxa_demangle(mangled, nullptr, nullptr, &status), std::free);
  return status == 0 && out ? std::string(out.get()) : std::string(mangled);
}

}  // namespace keel::detail

namespace keel {

std::string canonicalTypeName(std::string_view written) {
  std::string s;
  for (char ch : written)
    if (!std::isspace(static_cast<unsigned char>(ch))) s += ch;
  auto replaceAll = [&s](std::string_view from, std::string_view to) {
    for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size())
      s.replace(pos, from.size(), to);
  };
  replaceAll("std::string", "string");
  if (s.rfind("vector<", 0) == 0) s = "std::" + s;
  if (s.rfind("array<", 0) == 0) s = "std::" + s;
  static const std::pair<std::string_view, std::string_view> kAliases[] = {
      {"int32", "int"},
      {"int32_t", "int"},
      {"std::int32_t", "int"},
      {"int64", "long"},
      {"int64_t", "long"},
      {"std::int64_t", "long"},
      {"uint32", "unsigned"},
      {"uint32_t", "unsigned"},
      {"unsignedint", "unsigned"},
      {"uint64", "unsigned long"},
      {"uint64_t", "unsigned long"},
      {"unsignedlong", "unsigned long"},
      {"int8_t", "int8"},
      {"uint8_t", "uint8"},
      {"int16_t", "int16"},
      {"uint16_t", "uint16"},
      {"short", "int16"},
      {"longlong", "long long"},
      {"Event", "keel::Event"},
      {"FaultEvent", "keel::FaultEvent"},
      {"std::String", "string"},
  };
  for (auto [from, to] : kAliases)
    if (s == from) return std::string(to);
  return s;
}

}  // namespace keel
