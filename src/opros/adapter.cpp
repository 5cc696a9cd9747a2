#include "opros/adapter.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <type_traits>
#include <variant>

#include "runtime/component_core.hpp"

namespace keel::opros {
namespace {

QueuePolicy queuePolicy(DataPortPolicy p) {
  switch (p) {
    case OPROS_FIFO: return QueuePolicy::Fifo;
    case OPROS_LIFO: return QueuePolicy::Lifo;
    case OPROS_UFIFO: return QueuePolicy::UFifo;
    case OPROS_LAST: return QueuePolicy::Last;
  }
  return QueuePolicy::Fifo;
}

/// OPRoS's name of a code a callback returned, for the fault's detail.
const char* codeName(int code) {
  switch (static_cast<ReturnType>(code)) {
    case OPROS_CALLER_ERROR: return "OPROS_CALLER_ERROR";
    case OPROS_BAD_INPUT_PARAMETER: return "OPROS_BAD_INPUT_PARAMETER";
    case OPROS_INPUT_OUT_OF_RANGE: return "OPROS_INPUT_OUT_OF_RANGE";
    case OPROS_INPUT_NULL: return "OPROS_INPUT_NULL";
    case OPROS_UNAUTHORIZED: return "OPROS_UNAUTHORIZED";
    case OPROS_PRECONDITION_NOT_MET: return "OPROS_PRECONDITION_NOT_MET";
    case OPROS_OUT_OF_RESOURCES: return "OPROS_OUT_OF_RESOURCES";
    case OPROS_CALLEE_ERROR: return "OPROS_CALLEE_ERROR";
    case OPROS_UNSUPPORTED_METHOD: return "OPROS_UNSUPPORTED_METHOD";
    case OPROS_INTERNAL_FAULT: return "OPROS_INTERNAL_FAULT";
    case OPROS_VERSION_MISMATCH: return "OPROS_VERSION_MISMATCH";
    case OPROS_DESTORY_ERROR: return "OPROS_DESTORY_ERROR";
    case OPROS_FIND_DLL_ERROR: return "OPROS_FIND_DLL_ERROR";
    case OPROS_LOAD_DLL_ERROR: return "OPROS_LOAD_DLL_ERROR";
    case OPROS_FIND_PROPERTY_ERROR: return "OPROS_FIND_PROPERTY_ERROR";
    case OPROS_SET_PROPERTY_ERROR: return "OPROS_SET_PROPERTY_ERROR";
    case OPROS_INITIALIZE_API_ERROR: return "OPROS_INITIALIZE_API_ERROR";
    case OPROS_FINALIZE_API_ERROR: return "OPROS_FINALIZE_API_ERROR";
    case OPROS_RESET_API_ERROR: return "OPROS_RESET_API_ERROR";
    case OPROS_RECOVER_API_ERROR: return "OPROS_RECOVER_API_ERROR";
    case OPROS_RECOVER_ERROR: return "OPROS_RECOVER_ERROR";
    case OPROS_ENABLE_API_ERROR: return "OPROS_ENABLE_API_ERROR";
    case OPROS_DISABLE_API_ERROR: return "OPROS_DISABLE_API_ERROR";
    case OPROS_CALL_API_ERROR: return "OPROS_CALL_API_ERROR";
    case OPROS_API_NOT_SUPPORTED_ERROR: return "OPROS_API_NOT_SUPPORTED_ERROR";
    case OPROS_API_EXECUTING: return "OPROS_API_EXECUTING";
    case OPROS_VALID_DATA: return "OPROS_VALID_DATA";
    case OPROS_INVALID_DATA: return "OPROS_INVALID_DATA";
    case OPROS_ERROR: return "OPROS_ERROR";
    default: return "a code OPRoS does not name";
  }
}

/// A property as OPRoS had it: text. keel's typed value written back ("0.5", "true", "1,2,3").
std::string text(const PropertyValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) {
          return x ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return x;
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          return fmt::format("{}", fmt::join(x, ","));
        } else {
          return fmt::format("{}", x);
        }
      },
      v);
}

}  // namespace

Adapter::Adapter(::Component* object, Release release) : object_(object), release_(release) {
  detail::ComponentCore& core = runtime::coreOf(*this);
  core.opros = true;
  core.code_name = &codeName;
  for (const auto& [name, port] : object_->keelPorts()) {
    detail::PortBase& bound = port->keelBind(*this);
    if (port->getType() == OPROS_EVENT && bound.direction() == PortDirection::Input)
      event_inputs_.emplace_back(&bound, port);
    DataPortPolicy policy{};
    unsigned int limit = 0;
    if (port->keelCodeQueue(policy, limit)) core.code_queues[name] = {queuePolicy(policy), limit};
  }
}

Adapter::~Adapter() {
  if (release_) release_(object_);
  else delete object_;
}

ReturnCode Adapter::after(ReturnType r, LifecycleState on_success) {
  if (r == OPROS_SUCCESS || r == OPROS_SUCCESS_SYNC) {
    object_->keelSetStatus(on_success);
    return ReturnCode::Ok;
  }
  object_->error_info_ = r;
  return static_cast<ReturnCode>(static_cast<int>(r));
}

ReturnCode Adapter::onInitialize() {
  const detail::ComponentCore& core = runtime::coreOf(*this);
  object_->setId(instanceName());
  for (const auto& [name, value] : core.properties) object_->setProperty(name, text(value));
  if (!core.profile_file.empty())
    object_->keelSetResourcePath((std::filesystem::path(core.profile_file).parent_path() / "res").string() + "/");
  ReturnCode rc = after(object_->onInitialize(), OPROS_CS_READY);
  for (const auto& [addr, len] : object_->keelCritical()) critical(addr, len);
  return rc;
}

ReturnCode Adapter::onStart() { return after(object_->onStart(), OPROS_CS_ACTIVE); }
ReturnCode Adapter::onStop() { return after(object_->onStop(), OPROS_CS_INACTIVE); }
ReturnCode Adapter::onDestroy() { return after(object_->onDestroy(), OPROS_CS_DESTROYED); }
// Every cycle: the common case returns at once (the status is Active already).
ReturnCode Adapter::onExecute() {
  const ReturnType r = object_->onExecute();
  if (r == OPROS_SUCCESS) [[likely]]
    return ReturnCode::Ok;
  return after(r, OPROS_CS_ACTIVE);
}
ReturnCode Adapter::onUpdated() {
  const ReturnType r = object_->onUpdated();
  if (r == OPROS_SUCCESS) [[likely]]
    return ReturnCode::Ok;
  return after(r, OPROS_CS_ACTIVE);
}
ReturnCode Adapter::onError() { return after(object_->onError(), OPROS_CS_ERROR); }
ReturnCode Adapter::onReset() { return after(object_->onReset(), OPROS_CS_ERROR); }
// keel's reset ends with the component running again (decision 0012): Active, not OPRoS's Ready.
ReturnCode Adapter::onRecover() { return after(object_->onRecover(), OPROS_CS_ACTIVE); }

ReturnCode Adapter::onEvent(InputEventPortBase& port) {
  for (const auto& [bound, oport] : event_inputs_)
    if (bound == &port) return after(oport->keelDeliver(*object_), OPROS_CS_ACTIVE);
  return ReturnCode::Ok;
}

}  // namespace keel::opros

/// The entry point keel's loader looks up in an OPRoS component library (through the library's
/// dependency on libkeel_opros): a host of the object the library's getComponent() makes.
extern "C" keel::Component* keel_opros_adapter(void* get_component, void* release_component) {
  auto get = reinterpret_cast<::Component* (*)()>(get_component);
  auto release = reinterpret_cast<keel::opros::Release>(release_component);
  ::Component* object = get();
  if (!object) throw std::runtime_error("getComponent() returned NULL");
  try {
    return new keel::opros::Adapter(object, release);
  } catch (...) {
    if (release) release(object);
    else delete object;
    throw;
  }
}
