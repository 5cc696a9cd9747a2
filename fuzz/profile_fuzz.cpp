// libFuzzer target for the profile reader (src/profile): the input bytes become the root profile
// keel::profile::load() reads, as `keel run` and `keel validate` read the file they are given.
// Built six times (fuzz/CMakeLists.txt), once per root kind KEEL_FUZZ_ROOT names (`types`: OPRoS's
// service type and data type profiles, docs/opros.md#type-profiles; `node`: a ROS 2 node's): an input
// whose root element is another kind is rejected (kept out of the corpus), so that each target
// digs into its own parser. The root file is written beside a copy of the tests' valid profiles
// (KEEL_FUZZ_CONTEXT: valid/, system/ and node/, with the programs node profiles name), so that
// references and commands resolve and the cross-file validation runs too.
// Checked on every input: load() neither crashes, hangs nor throws (ASan+UBSan, libFuzzer's
// timeout); a failure has at least one diagnostic, each naming its file; a success holds the
// root under its kind and every warning names its file.
// Thread-safety: one input at a time, as libFuzzer calls it; the scratch tree is per process.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "profile/loader.hpp"

#ifndef KEEL_FUZZ_ROOT
#error "KEEL_FUZZ_ROOT must name the root kind: component, composite, package, system, types or node"
#endif

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kKind = KEEL_FUZZ_ROOT;

/// The scratch tree: a copy of the context, and the root file where its references resolve.
const std::string& rootPath() {
  static const std::string path = [] {
    const fs::path dir = fs::temp_directory_path() /
                         ("keel_fuzz_profile_" + std::string(kKind) + "_" + std::to_string(getpid()));
    fs::remove_all(dir);
    static const fs::path scratch = dir;
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(scratch, ignored);
    });
    for (const char* sub : {"valid", "system", "node"}) {
      fs::create_directories(dir / sub);
      fs::copy(fs::path(KEEL_FUZZ_CONTEXT) / sub, dir / sub, fs::copy_options::recursive);
    }
    const char* home = kKind == "system" ? "system" : kKind == "node" ? "node" : "valid";  // beside its kind's
    return (dir / home / "root.xml").string();
  }();
  return path;
}

bool isKind(keel::profile::RootKind k) {
  using keel::profile::RootKind;
  switch (k) {
    case RootKind::Component: return kKind == "component";
    case RootKind::Composite: return kKind == "composite";
    case RootKind::Package: return kKind == "package";
    case RootKind::System: return kKind == "system";
    case RootKind::ServiceType:
    case RootKind::DataType: return kKind == "types";
    case RootKind::Node: return kKind == "node";
    case RootKind::EngineConfig: return false;
  }
  return false;
}

/// The element name the target wants at the root.
bool rootIsMine(const std::string& path) {
  const std::string root = keel::profile::rootElementName(path);
  if (kKind == "component") return root == "component_profile";
  if (kKind == "composite") return root == "composite_component_profile";
  if (kKind == "package") return root == "package_profile" || root == "application_profile";
  if (kKind == "types") return root == "service_port_type_profile" || root == "data_type";
  if (kKind == "node") return root == "ros2_node_profile";
  return root == "system_profile";
}

[[noreturn]] void broken(const char* what) {
  std::fprintf(stderr, "profile_%s: %s\n", KEEL_FUZZ_ROOT, what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = rootPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return 0;
  const bool written = std::fwrite(data, 1, size, f) == size;
  std::fclose(f);
  if (!written) return 0;
  const bool mine = rootIsMine(path);
  auto result = keel::profile::load(path);
  if (!result.ok()) {
    if (result.error().empty()) broken("load failed without a diagnostic");
    for (const auto& d : result.error())
      if (d.where.file.empty() || d.str().empty()) broken("a diagnostic names no file");
    return mine ? 0 : -1;
  }
  if (!isKind(result->root_kind)) return -1;
  if (result->root != fs::weakly_canonical(path).string()) broken("the loaded root is not the file given");
  for (const auto& w : result->warnings)
    if (w.where.file.empty() || w.warningStr().find("warning: ") == std::string::npos) broken("a bad warning");
  return 0;
}
