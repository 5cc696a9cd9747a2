// The real engine as the benchmarks run it (recovery, scale): profiles loaded and an engine
// created over the benchmark's component libraries, every problem turned into one line of
// text for the cell's report.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "engine/engine.hpp"
#include "paths.hpp"
#include "profile/loader.hpp"

namespace keel::bench {

/// The profiles of `file`; on failure nothing, and every diagnostic in `error` ("; " between).
std::optional<profile::ProfileSet> loadProfiles(const std::string& file, std::string& error);

/// An engine over `set` (libraries from paths.components, the fault log written to `log`),
/// created, not started; its warnings go to `warn`. nullptr with the reason in `error`.
std::unique_ptr<engine::Engine> createEngine(profile::ProfileSet set, const Paths& paths, const std::string& log,
                                             std::function<void(const std::string&)> warn, std::string& error);

/// Starts it; false with the reason in `error`.
bool startEngine(engine::Engine& engine, std::string& error);

}  // namespace keel::bench
