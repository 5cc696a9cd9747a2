// libFuzzer target for the profile reader (src/profile): the input bytes become a profile file
// that keel::profile::load() reads; load() must never crash, hang or throw, whatever the bytes.
// Build (clang): clang++ -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined
//   -Iinclude -Isrc fuzz/profile_fuzz.cpp src/profile/*.cpp -lpugixml -lfmt -o profile_fuzz
// Thread-safety: one input at a time, as libFuzzer calls it; the temp file is per process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "profile/loader.hpp"

namespace {

/// A per-process scratch file. References inside the input resolve relative to its
/// directory, so the fuzzer may also reach the file itself (reference cycles).
const std::string& scratchPath() {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("keel_profile_fuzz_" + std::to_string(getpid()) + ".xml")).string();
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
  auto result = keel::profile::load(path);
  if (!result.ok()) {
    for (const auto& d : result.error()) (void)d.str();  // every message must be printable
  }
  return 0;
}
