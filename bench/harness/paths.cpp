#include "paths.hpp"

#include <filesystem>

namespace fs = std::filesystem;

namespace keel::bench {

Paths findPaths() {
  std::error_code ec;
  const fs::path bin = fs::canonical("/proc/self/exe", ec).parent_path();
  const fs::path prefix = bin.parent_path();
  Paths p;
  p.bin = bin.string();
  // The build tree has lib/; an install has ${CMAKE_INSTALL_LIBDIR} (lib, lib64 or a multiarch
  // lib/<triplet>), compiled in as KEEL_BENCH_LIBDIR.
  p.components = (prefix / "lib" / "keel" / "bench").string();
  if (!fs::is_directory(p.components, ec)) p.components = (prefix / KEEL_BENCH_LIBDIR / "keel" / "bench").string();
  p.profiles = (prefix / "share" / "keel" / "bench" / "profiles").string();
  p.peers = (prefix / "share" / "keel" / "bench" / "peers").string();
  p.child = (bin / "keel-bench-child").string();
  p.plot = (prefix / "share" / "keel" / "bench" / "plot_bench.py").string();
  return p;
}

}  // namespace keel::bench
