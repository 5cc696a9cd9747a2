// libFuzzer target for the fault scenario reader (src/fault/scenario): the input bytes become a
// scenario file that keel::fault::loadScenario() reads (software and hardware kinds, args);
// it must never crash, hang or throw, whatever the bytes.
// Build (clang): clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined
//   -Iinclude -Isrc fuzz/scenario_fuzz.cpp src/fault/scenario.cpp src/runtime/injection.cpp
//   src/profile/*.cpp -lpugixml -lfmt -o scenario_fuzz
// Thread-safety: one input at a time, as libFuzzer calls it; the temp file is per process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fault/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("keel_scenario_fuzz_" + std::to_string(getpid()) + ".xml")).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return 0;
  const bool written = std::fwrite(data, 1, size, f) == size;
  std::fclose(f);
  if (!written) return 0;
  auto result = keel::fault::loadScenario(path);
  if (!result.ok()) {
    for (const auto& d : result.error()) (void)d.str();  // every message must be printable
  } else {
    for (const auto& fault : result->faults) (void)fault.command();
  }
  return 0;
}
