// libFuzzer target for the fault scenario reader (src/injection/scenario): the input bytes become a
// scenario file that keel::injection::loadScenario() reads (software and hardware kinds, args);
// it must never crash, hang or throw, whatever the bytes, and a failure has a diagnostic.
// Built by the `fuzz` preset (fuzz/CMakeLists.txt); run by scripts/fuzz.sh scenario SECONDS.
// Thread-safety: one input at a time, as libFuzzer calls it; the temp file is per process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "injection/scenario.hpp"

namespace {

/// The scratch file, removed at exit.
const std::string& scratchPath() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("keel_scenario_fuzz_" + std::to_string(getpid()) + ".xml")).string();
  static const bool cleanup = std::atexit([] { std::remove(scratchPath().c_str()); }) == 0;
  (void)cleanup;
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = scratchPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return 0;
  const bool written = std::fwrite(data, 1, size, f) == size;
  std::fclose(f);
  if (!written) return 0;
  auto result = keel::injection::loadScenario(path);
  if (!result.ok()) {
    if (result.error().empty()) std::abort();            // a failure says why
    for (const auto& d : result.error()) (void)d.str();  // every message must be printable
  } else {
    for (const auto& fault : result->faults) (void)fault.command();
  }
  return 0;
}
