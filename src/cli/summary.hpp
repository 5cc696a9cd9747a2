// The one-screen summary `keel run` prints at the end: components, executors, faults, and how
// each fault was handled with its recovery latency (recovered − detected).
#pragma once

#include <ostream>

#include "engine/engine.hpp"

namespace keel::cli {

void printSummary(std::ostream& out, const engine::Engine& engine, double ran_s);
/// The handling part: per fault its severity, actions and recovery latency; totals.
void printHandling(std::ostream& out, const fault::FaultManager& manager);

}  // namespace keel::cli
