// The loader: finds component libraries (library_name relative to the profile, then each
// directory of KEEL_COMPONENT_PATH, then keel's own component directory next to libkeel),
// dlopens them once, and creates instances of registered classes — at start, or ahead of use
// for the alternatives preloaded. Libraries stay loaded until the Loader is destroyed.
// Thread-safety: load/create may be called from any thread (serialised internally).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "keel/component.hpp"
#include "keel/result.hpp"

namespace keel::runtime {

struct Library {
  std::string path;  // absolute
  void* handle = nullptr;
  std::vector<std::string> components;  // class names it registered
  // An OPRoS component library (docs/opros.md): it registered nothing and exports OPRoS's
  // getComponent()/releaseComponent(); one component type, whatever the profile calls it.
  void* opros_get = nullptr;      // getComponent; null: not an OPRoS library
  void* opros_release = nullptr;  // releaseComponent; null: the object is deleted
  // keel_opros_adapter from libkeel_opros (a dependency of the library when it was built with
  // keel_add_opros_component); null: built against OPRoS's own headers, keel cannot host it.
  Component* (*opros_adapter)(void*, void*) = nullptr;
};

class Loader {
 public:
  Loader();  // search path from the environment and libkeel's location
  explicit Loader(std::vector<std::string> search_path);
  ~Loader();
  Loader(const Loader&) = delete;
  Loader& operator=(const Loader&) = delete;

  /// KEEL_COMPONENT_PATH's directories, then <dir of libkeel>/keel.
  static std::vector<std::string> defaultSearchPath();
  const std::vector<std::string>& searchPath() const { return search_path_; }

  /// The file `library_name` names, tried relative to `profile_dir` then the search path.
  /// "foo", "libfoo.so", "foo.so" and OPRoS's "foo.dll" all find libfoo.so.
  Result<std::string> resolve(const std::string& library_name, const std::string& profile_dir) const;

  /// Loads the library at `path` (absolute) if not loaded yet.
  Result<const Library*> load(const std::string& path);

  /// A new instance of `class_name` from the library at `library_path` (loaded on demand); from
  /// an OPRoS component library, its one component whatever the name.
  Result<std::unique_ptr<Component>> create(const std::string& class_name, const std::string& library_path);

 private:
  Result<std::string> search(const std::string& library_name, const std::string& profile_dir) const;

  std::vector<std::string> search_path_;
  // (library name, profile dir) → the file found: every instance of a class asks the same.
  mutable std::mutex resolved_mutex_;
  mutable std::map<std::pair<std::string, std::string>, std::string> resolved_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Library>> libraries_;
};

}  // namespace keel::runtime
