// keel::ReturnCode: what a component callback returns. `Ok`, or an error carrying OPRoS's
// number. A non-Ok from onExecute is a fault of kind `error_code` (OPRoS ignored it; keel does
// not). Header-only, plain values.
#pragma once

#include <string_view>

namespace keel {

enum class ReturnCode : int {
  Ok = 0,
  BadInput = 400,            // OPROS_BAD_INPUT_PARAMETER
  CallApiError = 401,        // OPROS_CALL_API_ERROR
  InputOutOfRange = 402,     // OPROS_INPUT_OUT_OF_RANGE
  PreconditionNotMet = 405,  // OPROS_PRECONDITION_NOT_MET
  InternalFault = 500,       // OPROS_INTERNAL_FAULT
  Unsupported = 501,         // OPROS_UNSUPPORTED_METHOD
};

constexpr bool ok(ReturnCode rc) { return rc == ReturnCode::Ok; }

constexpr std::string_view toString(ReturnCode rc) {
  switch (rc) {
    case ReturnCode::Ok: return "ok";
    case ReturnCode::BadInput: return "bad input";
    case ReturnCode::CallApiError: return "call api error";
    case ReturnCode::InputOutOfRange: return "input out of range";
    case ReturnCode::PreconditionNotMet: return "precondition not met";
    case ReturnCode::InternalFault: return "internal fault";
    case ReturnCode::Unsupported: return "unsupported";
  }
  return "unknown return code";
}

}  // namespace keel
