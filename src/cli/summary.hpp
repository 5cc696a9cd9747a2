// The one-screen summary `keel run` prints at the end: components, executors, faults.
#pragma once

#include <ostream>

#include "runtime/engine.hpp"

namespace keel::cli {

void printSummary(std::ostream& out, const runtime::Engine& engine, double ran_s);

}  // namespace keel::cli
