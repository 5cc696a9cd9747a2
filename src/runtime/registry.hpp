// The registry of component classes: which library registered which class (KEEL_REGISTER_
// COMPONENT runs during dlopen). The loader opens a "capture" around each dlopen so that
// registrations are attributed to that library; registrations outside a capture belong to
// the program itself ("" library).
// Thread-safety: all functions lock an internal mutex.
#pragma once

#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include "keel/registry.hpp"

namespace keel::runtime {

struct Registration {
  std::string name;
  std::string library;  // absolute path, or "" for the program itself
  detail::Factory factory;
};

class Registry {
 public:
  static Registry& instance();

  /// Attributes registrations made until endCapture() to `library`.
  void beginCapture(const std::string& library);
  void endCapture();

  void add(const char* name, detail::Factory factory);
  /// The registration of `name` from `library`; when the library registered nothing of that
  /// name, one from the program itself. Null when none.
  const Registration* find(const std::string& name, const std::string& library) const;
  std::vector<Registration> fromLibrary(const std::string& library) const;

 private:
  Registry() = default;
  mutable std::recursive_mutex mutex_;
  std::string capturing_;
  std::deque<Registration> entries_;  // deque: find() pointers stay valid
};

}  // namespace keel::runtime
