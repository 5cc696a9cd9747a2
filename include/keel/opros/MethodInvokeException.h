// MethodInvokeException.h — keel's own, from-scratch OPRoS-compatible version of the exception
// a service method call throws when it cannot be made (e.g. a required method that is not
// connected). A std::exception (OPRoS's was not), so `catch (std::exception&)` sees it too.
#pragma once

#include <exception>
#include <string>

class MethodInvokeException : public std::exception {
 public:
  explicit MethodInvokeException(const std::string& message) : message_(message) {}

  std::string& getMessage() { return message_; }
  const std::string& getMessage() const { return message_; }
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};
