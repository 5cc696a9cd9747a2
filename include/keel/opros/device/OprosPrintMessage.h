// OprosPrintMessage.h — keel's own, from-scratch OPRoS-compatible version of the device API's
// PrintMessage: printf to standard output. (OPRoS printed only in builds that defined
// _OPROS_DEBUG_, _DEBUG or, in 2012, NDEBUG; keel always prints.) Thread-safe as printf is.
#ifndef KEEL_OPROS_DEVICE_OPROS_PRINT_MESSAGE_H
#define KEEL_OPROS_DEVICE_OPROS_PRINT_MESSAGE_H

#include <cstdarg>
#include <cstdio>

#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
inline void
PrintMessage(const char* format, ...) {
  va_list arguments;
  va_start(arguments, format);
  std::vprintf(format, arguments);
  va_end(arguments);
}

#endif  // KEEL_OPROS_DEVICE_OPROS_PRINT_MESSAGE_H
