#include "runtime/loader.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "runtime/registry.hpp"

namespace fs = std::filesystem;

namespace keel::runtime {
namespace {

std::vector<std::string> candidates(const std::string& name) {
  fs::path p(name);
  std::string stem = p.filename().string();
  std::string dir = p.parent_path().string();
  auto in = [&dir](const std::string& f) { return dir.empty() ? f : dir + "/" + f; };
  std::vector<std::string> out{name};
  if (p.extension() == ".dll" || p.extension() == ".so") stem = p.stem().string();
  if (stem.rfind("lib", 0) != 0) out.push_back(in("lib" + stem + ".so"));
  out.push_back(in(stem + ".so"));
  return out;
}

}  // namespace

Loader::Loader() : Loader(defaultSearchPath()) {}
Loader::Loader(std::vector<std::string> search_path) : search_path_(std::move(search_path)) {}

Loader::~Loader() {
  for (auto it = libraries_.rbegin(); it != libraries_.rend(); ++it)
    if ((*it)->handle) dlclose((*it)->handle);
}

std::vector<std::string> Loader::defaultSearchPath() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("KEEL_COMPONENT_PATH")) {
    std::string s(env);
    for (std::size_t start = 0; start <= s.size();) {
      std::size_t end = s.find(':', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) out.push_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&Loader::defaultSearchPath), &info) && info.dli_fname) {
    std::error_code ec;
    fs::path lib = fs::canonical(info.dli_fname, ec);
    if (!ec) out.push_back((lib.parent_path() / "keel").string());
  }
  return out;
}

Result<std::string> Loader::resolve(const std::string& library_name, const std::string& profile_dir) const {
  const auto key = std::make_pair(library_name, profile_dir);
  {
    std::lock_guard lock(resolved_mutex_);
    if (const auto it = resolved_.find(key); it != resolved_.end()) return it->second;
  }
  auto found = search(library_name, profile_dir);
  if (found) {
    std::lock_guard lock(resolved_mutex_);
    resolved_.emplace(key, *found);
  }
  return found;
}

Result<std::string> Loader::search(const std::string& library_name, const std::string& profile_dir) const {
  std::vector<std::string> tried;  // each file once, however often its directory is named
  auto tryDir = [&](const fs::path& dir) -> std::string {
    for (const auto& c : candidates(library_name)) {
      fs::path p = fs::path(c).is_absolute() ? fs::path(c) : dir / c;
      std::error_code ec;
      fs::path key = fs::weakly_canonical(p, ec);
      if (ec) key = p.lexically_normal();
      if (std::find(tried.begin(), tried.end(), key.string()) != tried.end()) continue;
      if (fs::is_regular_file(p, ec)) return fs::canonical(p, ec).string();
      tried.push_back(key.string());
    }
    return {};
  };
  if (auto f = tryDir(profile_dir); !f.empty()) return f;
  for (const auto& d : search_path_)
    if (auto f = tryDir(d); !f.empty()) return f;
  std::string msg = fmt::format("library '{}' not found; tried:", library_name);
  for (const auto& t : tried) msg += "\n  " + t;
  if (!std::getenv("KEEL_COMPONENT_PATH")) msg += "\n  (KEEL_COMPONENT_PATH is not set)";
  return fail(msg);
}

Result<const Library*> Loader::load(const std::string& path) {
  std::lock_guard lock(mutex_);
  for (const auto& lib : libraries_)
    if (lib->path == path) return lib.get();
  Registry& registry = Registry::instance();
  registry.beginCapture(path);
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  registry.endCapture();
  if (!handle) return fail(fmt::format("cannot load '{}': {}", path, dlerror()));
  auto lib = std::make_unique<Library>();
  lib->path = path;
  lib->handle = handle;
  for (const auto& r : registry.fromLibrary(path)) lib->components.push_back(r.name);
  if (lib->components.empty()) {
    lib->opros_get = dlsym(handle, "getComponent");
    lib->opros_release = dlsym(handle, "releaseComponent");
    // dlsym on the library's handle also searches what it depends on: libkeel_opros.
    if (lib->opros_get)
      lib->opros_adapter = reinterpret_cast<Component* (*)(void*, void*)>(dlsym(handle, "keel_opros_adapter"));
  }
  libraries_.push_back(std::move(lib));
  return libraries_.back().get();
}

Result<std::unique_ptr<Component>> Loader::create(const std::string& class_name, const std::string& library_path) {
  auto lib = load(library_path);
  if (!lib) return lib.error();
  if ((*lib)->opros_get) {
    if (!(*lib)->opros_adapter)
      return fail(
          fmt::format("library '{}' is an OPRoS component library (it exports getComponent) built without keel's OPRoS "
                      "layer; build its sources with keel_add_opros_component",
                      library_path));
    try {
      return std::unique_ptr<Component>((*lib)->opros_adapter((*lib)->opros_get, (*lib)->opros_release));
    } catch (const std::exception& e) {
      return fail(fmt::format("constructing OPRoS component '{}' failed: {}", class_name, e.what()));
    }
  }
  const Registration* r = Registry::instance().find(class_name, library_path);
  if (!r) {
    std::string have;
    for (const auto& n : (*lib)->components) have += (have.empty() ? "" : ", ") + n;
    return fail(fmt::format("library '{}' registers no component '{}' (it has: {})", library_path, class_name,
                            have.empty() ? "none" : have));
  }
  try {
    return r->factory();
  } catch (const std::exception& e) {
    return fail(fmt::format("constructing '{}' failed: {}", class_name, e.what()));
  }
}

}  // namespace keel::runtime
