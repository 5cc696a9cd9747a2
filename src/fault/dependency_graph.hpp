// The dependency graph of a plan (paper §5.2, Fig. 7): which components each application needs
// (for duplicates, at least `min_healthy` of a `requires` group), which applications depend on
// which (`depends_on`), which components depend on which (`coordination/needs`), and each
// component's executor. The fault manager asks it, at fault time, what a fault stops: the
// containment scope (component, executor, composite, system), every application that can no longer run,
// and every component of those. `keel graph --fail` prints the same answer.
// Thread-safety: immutable once built; every const member may be called from any thread.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "keel/result.hpp"
#include "plan/plan.hpp"
#include "profile/loader.hpp"
#include "profile/model.hpp"

namespace keel::fault {

/// What a set of stopped components brings down.
struct Impact {
  std::vector<std::string> stopped_components;    // plan order; the given ones included
  std::vector<std::string> stopped_applications;  // profile order
  std::vector<std::string> running_applications;  // profile order
};

class DependencyGraph {
 public:
  /// Indexes `plan`; `set` gives the applications (a package, composite or component root is
  /// one implicit application named after it, running while any component runs). Fails on names that do
  /// not resolve (the loader rejects those first; this only guards against a plan and set
  /// that do not belong together). Dependency cycles are tolerated: they stop together.
  [[nodiscard]] static Result<DependencyGraph> build(const plan::Plan& plan, const profile::ProfileSet& set);

  /// Everything that stops when the components in `failed` stop: an application stops when a
  /// requirement group has fewer than `min_healthy` healthy entries, or when an application it
  /// depends on stops; the components of a stopped application stop; a component stops when
  /// one it depends on (coordination/needs) stops. Names not in the graph are ignored.
  Impact impactOf(const std::set<std::string>& failed) const;

  /// The containment scope of a fault stop of `component`: itself, every member of its
  /// executor (itself when passive), or every component. Empty for an unknown name.
  std::set<std::string> scopeOf(const std::string& component, profile::Scope scope) const;

  /// impactOf(scopeOf(component, scope)).
  Impact blastRadius(const std::string& component, profile::Scope scope) const;

  /// The scope `component`'s fault policy names (<dependency>), `Component` when it has none.
  profile::Scope policyScope(const std::string& component) const;

  bool contains(const std::string& component) const { return index_.count(component) != 0; }
  /// Component names, plan order.
  const std::vector<std::string>& components() const { return names_; }

 private:
  using Id = std::size_t;  // index of a component, application, group or entry
  static constexpr Id kNone = static_cast<Id>(-1);

  /// A requirement group: `size` entries (a component, or the components of a composite), of
  /// which `min_healthy` must have no stopped component.
  struct Group {
    Id app = 0;
    std::size_t min_healthy = 1;
    std::size_t size = 0;
  };
  /// A component counts in entry `entry` of group `group` (entries are numbered graph-wide).
  struct Use {
    Id group = 0;
    Id entry = 0;
  };
  struct App {
    std::string name;
    std::vector<Id> members;
    std::vector<Id> dependants;  // applications that depend on this one
  };

  DependencyGraph() = default;
  Impact impactOfIds(const std::vector<Id>& failed) const;
  std::vector<Id> scopeIds(const std::string& component, profile::Scope scope) const;
  std::vector<Id> resolve(const std::string& name) const;
  Result<void> indexComponents(const plan::Plan& plan);
  Result<void> indexDepends(const plan::Plan& plan);
  Result<void> indexApplications(const plan::Plan& plan, const profile::ProfileSet& set);
  Result<void> addGroup(Id app, const std::vector<std::vector<Id>>& entries, std::size_t min_healthy);

  std::vector<std::string> names_;
  std::map<std::string, Id, std::less<>> index_;
  std::vector<profile::Scope> policy_scope_;  // per component
  std::vector<Id> executor_of_;               // per component; kNone: passive, no executor
  std::vector<std::vector<Id>> executors_;    // members of each executor
  std::vector<Id> composite_of_;              // per component: its innermost composite; kNone: none
  std::vector<std::vector<Id>> composites_;   // members of each composite (nested ones' included)
  std::vector<std::vector<Id>> dependants_;   // per component: who depends on it
  std::vector<std::vector<Use>> uses_;        // per component: the entries it counts in
  std::vector<Group> groups_;
  std::size_t entries_ = 0;
  std::vector<App> apps_;
};

}  // namespace keel::fault
