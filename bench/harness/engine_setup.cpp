#include "engine_setup.hpp"

#include "report.hpp"

namespace keel::bench {

std::optional<profile::ProfileSet> loadProfiles(const std::string& file, std::string& error) {
  auto set = profile::load(file);
  if (set) return std::move(*set);
  for (const auto& d : set.error()) addNote(error, d.str());
  if (error.empty()) error = "cannot load " + file;
  return std::nullopt;
}

std::unique_ptr<engine::Engine> createEngine(profile::ProfileSet set, const Paths& paths, const std::string& log,
                                             std::function<void(const std::string&)> warn, std::string& error) {
  engine::EngineOptions opts;
  opts.log_path = log;
  opts.search_path = {paths.components};
  opts.warn = std::move(warn);
  auto engine = engine::Engine::create(std::move(set), std::move(opts));
  if (!engine) {
    error = "engine: " + engine.error().message;
    return nullptr;
  }
  return std::move(*engine);
}

bool startEngine(engine::Engine& engine, std::string& error) {
  if (auto r = engine.start(); !r) {
    error = "start: " + r.error().message;
    return false;
  }
  return true;
}

}  // namespace keel::bench
