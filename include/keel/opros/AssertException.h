// AssertException.h — keel's own OPRoS-compatible version of the exception opros_assert throws.
//
// OPRoS's opros_assert threw a bare std::exception; keel's throws this, which is a
// std::logic_error (so `catch (std::exception&)` still catches it) and says which condition
// failed where. Header-only.
#pragma once

#include <iostream>
#include <stdexcept>
#include <string>

class AssertException : public std::logic_error {
 public:
  AssertException() : std::logic_error("opros_assert failed") {}
  AssertException(const char* condition, const char* file, int line)
      : std::logic_error(std::string("opros_assert(") + condition + ") failed at " + file + ":" +
                         std::to_string(line)) {}

  // OPRoS's way to report it: prints the message to std::cerr.
  void message() const { std::cerr << what() << std::endl; }
};
