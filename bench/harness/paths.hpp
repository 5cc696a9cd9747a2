// Where `keel bench` finds what it runs: its component libraries, its packages, the peers'
// sources and the respawned child. All relative to the keel-bench program, so the build tree
// (build/bin, build/lib/keel/bench, build/share/keel/bench) and an installed prefix work alike.
#pragma once

#include <string>

namespace keel::bench {

struct Paths {
  std::string bin;         // the directory of keel-bench (and keel, keel-bench-child)
  std::string components;  // <lib>/keel/bench: the benchmark's component libraries
  std::string profiles;    // <share>/keel/bench/profiles: the benchmark's packages
  std::string peers;       // <share>/keel/bench/peers: the Erlang peer's sources
  std::string child;       // <bin>/keel-bench-child: the process the respawn peer restarts
  std::string plot;        // <share>/keel/bench/plot_bench.py: the plots, from the JSON
};

/// Found from /proc/self/exe; a missing directory is reported when it is first used.
Paths findPaths();

}  // namespace keel::bench
