// What the fault manager needs from whoever runs the components (the engine): lookups by
// instance name, and the three operations of recovery that change the wiring — creating an
// alternative, switching a role to it, abandoning a hung executor. The fault layer defines it;
// the engine, above, implements it.
// Thread-safety: as stated per operation.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "keel/component.hpp"
#include "keel/result.hpp"

namespace keel::fault {

struct ComponentHandling;

class RecoveryActions {
 public:
  virtual ~RecoveryActions() = default;
  /// The serving component of `instance` (null: unknown). Any thread.
  virtual Component* find(std::string_view instance) const = 0;
  /// Every running component (replacements in place of what they replaced). Any thread.
  virtual std::vector<Component*> components() const = 0;
  /// Cold replacement, on the manager's thread: loads, creates, initializes and wires the
  /// alternative of `failed` (outputs attached, not started, not yet receiving).
  virtual Result<Component*> createAlternative(ComponentHandling& h, Component& failed) = 0;
  /// On `failed`'s own thread: `alternative` takes its place — inputs retargeted, provided
  /// services rebound, executor member swapped, lookups by name answer the alternative.
  virtual void switchTo(Component& failed, Component& alternative) = 0;
  /// `hung`'s executor thread is stuck in its callback and cannot be interrupted: the executor
  /// is abandoned and a new one (same configuration) takes its other members, and
  /// `alternative` (may be null) in `hung`'s place, started on the calling thread before the
  /// new executor runs. Returns the new executor's name, or why it could not be done.
  virtual Result<std::string> abandonExecutor(Component& hung, Component* alternative) = 0;
};

}  // namespace keel::fault
