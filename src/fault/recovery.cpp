#include "fault/recovery.hpp"

#include <fmt/compile.h>

#include <mutex>
#include <string>

#include "log/fault_log.hpp"
#include "runtime/checkpoint.hpp"
#include "runtime/component_core.hpp"
#include "runtime/invoke.hpp"

namespace keel::fault {

using runtime::coreOf;

Outcome Recovery::intensityAt(ComponentHandling& h, std::int64_t now_ns) const {
  std::lock_guard lock(h.mutex);
  return h.window.exceededAt(now_ns) ? Outcome::IntensityExceeded : Outcome::Done;
}

void Recovery::noteRecovery(ComponentHandling& h, std::int64_t t) {
  std::lock_guard lock(h.mutex);
  h.window.note(t);
}

void Recovery::markRecovering(const FaultReport& r, Component& c) {
  coreOf(c).fault.recovering_id.store(r.id, std::memory_order_release);
}

Outcome Recovery::reset(FaultReport& r, ComponentHandling& h) {
  Component& c = *r.accused;
  auto& core = coreOf(c);
  if (c.state() != State::Error) r.noteState(runtime::setStateQuiet(c, State::Error));
  runtime::GuardOutcome failed;
  for (runtime::Callback cb : {runtime::Callback::Error, runtime::Callback::Reset}) {
    runtime::GuardOutcome out = runtime::invokeRecovery(c, cb);
    if (!out.ok() && failed.ok()) failed = out;
  }
  const std::int64_t checkpoint_t = runtime::restoreCheckpoint(core);
  core.injection.stalled_until_ns.store(0, std::memory_order_relaxed);
  if (failed.ok()) failed = runtime::invokeRecovery(c, runtime::Callback::Recover);
  const std::int64_t t = runtime::steadyNs();
  if (!failed.ok()) {
    FaultEvent why;
    failed.describe(why, "recovery");
    r.add(ActionKind::Reset, false, t, "{}", why.detailText());
    return Outcome::Failed;
  }
  // The watchdog's "not executed" counts from here, not from the step that failed (a hung one
  // began longer ago than the timeout: a second fault before the next step could run).
  core.watch.last_beat_ns.store(t, std::memory_order_relaxed);
  r.noteState(runtime::setStateQuiet(c, State::Active));
  r.add(ActionKind::Reset, true, t, FMT_COMPILE("onError → onReset → onRecover"));
  if (!core.critical.empty()) {
    if (checkpoint_t != 0)
      r.add(ActionKind::Restore, true, t,
            FMT_COMPILE("critical memory restored from the checkpoint of {:.3f} ms before"),
            (r.event.t_ns - checkpoint_t) / 1e6);
    else r.add(ActionKind::Restore, false, t, FMT_COMPILE("no checkpoint yet: critical memory left as it was"));
  }
  noteRecovery(h, t);
  markRecovering(r, c);
  return Outcome::Done;
}

Outcome Recovery::load(FaultReport& r, ComponentHandling& h) {
  auto alt = actions_ ? actions_->createAlternative(h, *r.accused) : Result<Component*>(fail("no runtime"));
  if (!alt) {
    r.add(ActionKind::Replace, false, runtime::steadyNs(), "loading the alternative failed: {}", alt.error().message);
    return Outcome::Failed;
  }
  std::lock_guard lock(h.mutex);
  h.ready_alternative = *alt;
  return Outcome::Done;
}

Outcome Recovery::replace(FaultReport& r, ComponentHandling& h) {
  Component* alt = nullptr;
  bool preloaded = false;
  {
    std::lock_guard lock(h.mutex);
    alt = h.ready_alternative;
    h.ready_alternative = nullptr;
    h.replaced = true;
    preloaded = h.rules.preload;
  }
  Component& failed = *r.accused;
  const std::size_t copied = runtime::copyCheckpoint(coreOf(failed), coreOf(*alt));
  actions_->switchTo(failed, *alt);
  r.alternative = alt;
  runtime::GuardOutcome out = runtime::invokeRecovery(*alt, runtime::Callback::Start);
  const std::int64_t t = runtime::steadyNs();
  if (!out.ok()) {
    r.noteState(runtime::setStateQuiet(*alt, State::Error));
    FaultEvent why;
    out.describe(why, "onStart");
    r.add(ActionKind::Replace, false, t, "alternative {}: {}", coreOf(*alt).class_name, why.detailText());
    return Outcome::Failed;
  }
  r.noteState(runtime::setStateQuiet(*alt, State::Active));
  // Its own first checkpoint: what a later reset of the alternative returns to (the buffers
  // exist since its creation, so nothing is allocated here).
  if (!coreOf(*alt).critical.empty()) runtime::takeCheckpoint(coreOf(*alt), t);
  r.add(ActionKind::Replace, true, t, FMT_COMPILE("alternative {} ({}) took over{}"), coreOf(*alt).class_name,
        preloaded ? "preloaded" : "loaded at fault time", copied ? " with the checkpointed state" : "");
  noteRecovery(h, t);
  markRecovering(r, *alt);
  return Outcome::Done;
}

void Recovery::abandon(FaultReport& r, ComponentHandling& h) {
  Component& hung = *r.accused;
  const Step from = r.next;
  Component* alt = nullptr;
  RoleFacts facts;
  {
    std::lock_guard lock(h.mutex);
    facts = h.facts();
    alt = h.ready_alternative;
  }
  if (facts.has_alternative && !facts.replaced && alt == nullptr && actions_) {
    auto made = actions_->createAlternative(h, hung);
    if (made) alt = *made;
    else
      r.add(ActionKind::Replace, false, runtime::steadyNs(), "loading the alternative failed: {}",
            made.error().message);
  }
  if (alt) runtime::copyCheckpoint(coreOf(hung), coreOf(*alt));
  facts.alternative_ready = alt != nullptr;
  const Decision d = decide(from, Outcome::Hung, facts);
  r.add(ActionKind::Escalate, true, runtime::steadyNs(), "{} → {}: {}", toString(from), toString(d.next), d.why);
  auto moved = actions_ ? actions_->abandonExecutor(hung, alt) : Result<std::string>(fail("no runtime"));
  const std::int64_t t = runtime::steadyNs();
  if (!moved) {
    r.add(ActionKind::Stop, false, t, "executor not abandoned: {}", moved.error().message);
    r.next = Step::Stop;
    return;
  }
  if (alt) {
    {
      std::lock_guard lock(h.mutex);
      h.ready_alternative = nullptr;
      h.replaced = true;
      h.window.note(t);
    }
    r.alternative = alt;
    const bool started = alt->state() == State::Active;
    r.add(ActionKind::Replace, started, t, "alternative {} took over on the new executor {}", coreOf(*alt).class_name,
          *moved);
    if (started) markRecovering(r, *alt);
    r.next = started ? Step::Done : Step::Stop;
  } else {
    r.add(ActionKind::Stop, true, t, "executor abandoned; its other components now run on {}", *moved);
    r.next = Step::Stop;
  }
}

}  // namespace keel::fault
