// keel's OPRoS compatibility: the umbrella OPRoS component sources include for the symbol
// service, event callbacks and the resource path, and getVersion(), the entry point OPRoS's
// 2014 engine asked a component library for. getVersion is defined here as OPRoS did, but weak,
// so that two translation units of one library may both include this header.
#pragma once

#include "EventCallBack.h"
#include "PackageUtil.h"
#include "SymbolService.h"

#ifndef KEEL_OPROS_VERSION
#define KEEL_OPROS_VERSION "keel-opros-1"
#endif

#ifndef MAKE_STATIC_COMPONENT
extern "C" __attribute__((weak)) const char* getVersion() { return KEEL_OPROS_VERSION; }
#endif
