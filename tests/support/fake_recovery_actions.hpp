// Test support: the engine's side of fault handling (fault::RecoveryActions), faked over a list of
// components for the fault manager's parts without an engine. It finds the components by
// instance name; it has no alternative to create and no executor to abandon.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fault/recovery_actions.hpp"

namespace keel::test {

class FakeRecoveryActions : public fault::RecoveryActions {
 public:
  std::vector<Component*> all;  // the running components

  Component* find(std::string_view name) const override {
    for (Component* c : all)
      if (c->instanceName() == name) return c;
    return nullptr;
  }
  std::vector<Component*> components() const override { return all; }
  Result<Component*> createAlternative(fault::ComponentHandling&, Component&) override {
    return fail("no alternative");
  }
  void switchTo(Component&, Component&) override {}
  Result<std::string> abandonExecutor(Component&, Component*) override { return fail("no executor to abandon"); }

  /// find(), as the fault manager and its parts take their lookup by instance name.
  std::function<Component*(std::string_view)> lookup() const {
    return [this](std::string_view name) { return find(name); };
  }
};

}  // namespace keel::test
