// Test support: a scratch file in the temporary directory, and a fault log written to one and
// read back with log_reader.hpp.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "log/fault_log.hpp"
#include "support/log_reader.hpp"

namespace keel::test {

/// `<temporary directory>/<stem>_<pid><extension>`: one file per process, so that test binaries
/// (and ctest's processes, one per test) running side by side do not share it.
inline std::string tempPath(const std::string& stem, const std::string& extension = ".jsonl") {
  return (std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + extension)).string();
}

/// A fault log on a temporary file: open (truncated) from construction, removed at destruction.
struct TempLog {
  explicit TempLog(const std::string& stem = "keel_fault_log") : path(tempPath(stem)) { EXPECT_TRUE(log.open(path)); }
  ~TempLog() { std::filesystem::remove(path); }
  TempLog(const TempLog&) = delete;
  TempLog& operator=(const TempLog&) = delete;

  /// Every record written so far, in order.
  std::vector<nlohmann::json> read() const { return readLog(path); }

  std::string path;
  log::FaultLog log;
};

}  // namespace keel::test
