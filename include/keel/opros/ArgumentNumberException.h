// ArgumentNumberException.h — keel's own, from-scratch OPRoS-compatible version of the exception
// a service method call throws when it gets another number of arguments than the method takes.
// A std::exception (OPRoS's was not).
#pragma once

#include <exception>
#include <sstream>
#include <string>

class ArgumentNumberException : public std::exception {
 public:
  // line: where the call was made; arity: how many arguments the method takes.
  ArgumentNumberException(int line, int arity) : line_(line), arity_(arity), message_(describe(line, arity)) {}

  std::string& getMessage() { return message_; }
  const std::string& getMessage() const { return message_; }
  const char* what() const noexcept override { return message_.c_str(); }

  int getLine() const { return line_; }
  int getArity() const { return arity_; }

 private:
  static std::string describe(int line, int arity) {
    std::ostringstream text;
    text << "line " << line << ": the method requires " << arity << " argument" << (arity == 1 ? "" : "s");
    return text.str();
  }

  int line_;
  int arity_;
  std::string message_;
};
