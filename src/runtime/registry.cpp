#include "runtime/registry.hpp"

#include <mutex>

namespace keel::runtime {

Registry& Registry::instance() {
  static auto* registry = new Registry();  // never destroyed: plugins may outlive statics
  return *registry;
}

void Registry::beginCapture(const std::string& library) {
  mutex_.lock();  // held until endCapture: one dlopen at a time
  capturing_ = library;
}

void Registry::endCapture() {
  capturing_.clear();
  mutex_.unlock();
}

void Registry::add(const char* name, detail::Factory factory) {
  std::lock_guard lock(mutex_);
  for (auto& e : entries_) {
    if (e.name == name && e.library == capturing_) {
      e.factory = factory;  // the same library loaded again after an unload
      return;
    }
  }
  entries_.push_back({name, capturing_, factory});
}

const Registration* Registry::find(const std::string& name, const std::string& library) const {
  std::lock_guard lock(mutex_);
  const Registration* fallback = nullptr;
  for (const auto& e : entries_) {
    if (e.name != name) continue;
    if (e.library == library) return &e;
    if (e.library.empty()) fallback = &e;
  }
  return fallback;
}

std::vector<Registration> Registry::fromLibrary(const std::string& library) const {
  std::lock_guard lock(mutex_);
  std::vector<Registration> out;
  for (const auto& e : entries_)
    if (e.library == library) out.push_back(e);
  return out;
}

}  // namespace keel::runtime

bool keel::detail::registerComponent(const char* name, Factory factory) noexcept {
  keel::runtime::Registry::instance().add(name, factory);
  return true;
}
