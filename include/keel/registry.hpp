// KEEL_REGISTER_COMPONENT(Class): makes a component class loadable by name. Several classes
// may be registered per library. Registration happens while the runtime dlopens the library
// (static initialisation), which is how the runtime knows which library provides what.
// Thread-safety: registration is serialised by the runtime's loader.
#pragma once

#include <memory>

namespace keel {
class Component;
}

namespace keel::detail {

using Factory = std::unique_ptr<Component> (*)();

/// Records a component class. Defined in libkeel; returns true so it can initialise a static.
bool registerComponent(const char* name, Factory factory) noexcept;

/// The factory of `Class`: a plain function, so that the registration itself (a static's
/// initialiser) calls nothing that throws: a constructor that throws does so when an instance
/// is created, not while its library loads.
template <class Class>
std::unique_ptr<Component> make() {
  return std::make_unique<Class>();
}

}  // namespace keel::detail

#define KEEL_DETAIL_CAT2(a, b) a##b
#define KEEL_DETAIL_CAT(a, b) KEEL_DETAIL_CAT2(a, b)

/// Registers `Class` under the name `NAME` (a string literal).
#define KEEL_REGISTER_COMPONENT_AS(Class, NAME)                                \
  namespace {                                                                  \
  [[maybe_unused]] const bool KEEL_DETAIL_CAT(keel_registered_, __COUNTER__) = \
      ::keel::detail::registerComponent(NAME, &::keel::detail::make<Class>);   \
  }

/// Registers `Class` under its own name, as written ("Sonar", or "robot::Sonar").
#define KEEL_REGISTER_COMPONENT(Class) KEEL_REGISTER_COMPONENT_AS(Class, #Class)
