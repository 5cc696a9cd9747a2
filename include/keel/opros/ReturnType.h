// ReturnType.h — keel's own, from-scratch OPRoS-compatible version of OPRoS's result codes.
//
// OPRoS components store these codes in `ReturnType` variables, return them from callbacks and
// service methods and compare them, so every code is a plain integral constant (a macro, as in
// OPRoS) that converts both ways; an `enum class` would break that code. Values: OPRoS's
// published ones, with the two recoverable device codes the 2015 header misprinted given their
// intended values.
// Header-only, no state: usable from any thread.
#pragma once

typedef unsigned int ReturnType;

// Success.
#define OPROS_SUCCESS 200
#define OPROS_SUCCESS_SYNC 202

// The caller's fault.
#define OPROS_CALLER_ERROR 400
#define OPROS_BAD_INPUT_PARAMETER 401
#define OPROS_INPUT_OUT_OF_RANGE 402
#define OPROS_INPUT_NULL 403
#define OPROS_UNAUTHORIZED 404
#define OPROS_PRECONDITION_NOT_MET 405
#define OPROS_OUT_OF_RESOURCES 408

// The callee's fault.
#define OPROS_CALLEE_ERROR 500
#define OPROS_UNSUPPORTED_METHOD 501
#define OPROS_INTERNAL_FAULT 502
#define OPROS_VERSION_MISMATCH 505

// Device API, unrecoverable (0x1000xxxx). DESTORY is OPRoS's own spelling.
#define OPROS_DESTORY_ERROR 0x10000000
#define OPROS_FIND_DLL_ERROR 0x10000001
#define OPROS_LOAD_DLL_ERROR 0x10000002
#define OPROS_FIND_PROPERTY_ERROR 0x10000003
#define OPROS_SET_PROPERTY_ERROR 0x10000004
#define OPROS_INITIALIZE_API_ERROR 0x10000100
#define OPROS_FINALIZE_API_ERROR 0x10000101
#define OPROS_RESET_API_ERROR 0x10000102
#define OPROS_RECOVER_API_ERROR 0x10000103

// Device API, recoverable (0x2000xxxx).
#define OPROS_RECOVER_ERROR 0x20000000
#define OPROS_ENABLE_API_ERROR 0x20000100
#define OPROS_DISABLE_API_ERROR 0x20000101
#define OPROS_CALL_API_ERROR 0x20000102
#define OPROS_API_NOT_SUPPORTED_ERROR 0x20000103
#define OPROS_API_EXECUTING 0x20000104

// Found only in some vendor copies of the header.
#define OPROS_VALID_DATA 300
#define OPROS_INVALID_DATA 301
#define OPROS_ERROR 302

// UNKNOWN_ERROR is too common a name to be a macro (it would rewrite a vendor SDK's enumerator
// of that name); a constant does the same for OPRoS code. Skipped when someone #defined it.
#ifndef UNKNOWN_ERROR
inline constexpr ReturnType UNKNOWN_ERROR = 210;
#endif
