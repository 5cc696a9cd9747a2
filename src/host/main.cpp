// keel-host: one component process of a `keel run` (docs/isolation.md). keel run starts it with
// the run's own arguments (the profile, --set, --inject, --log, --log-tee) and the host's: which <process>
// it runs, its slot, the session and ring descriptors it inherited, whether it is a standby.
// It plans the same run, loads and initialises only the components of its process, and runs
// them as the active host, or waits as a standby to take over (src/supervision/process_host.hpp).
// Not meant to be started by hand.
//
// Exit status: 0 stopped by keel run; 1 could not start (the reason is in its slot, which keel
// run prints); 2 bad arguments or profiles; 70 keel run died (after the emergency stop); 71
// fenced (a standby took its place).
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <iostream>
#include <string>
#include <vector>

#include "engine/engine.hpp"
#include "injection/scenario.hpp"
#include "plan/property_settings.hpp"
#include "profile/loader.hpp"
#include "supervision/process_host.hpp"

namespace {

using keel::engine::Engine;
using keel::supervision::HostRole;
using keel::supervision::ProcessHost;

struct Args {
  std::string profile;
  std::vector<std::string> sets;
  std::string inject;
  std::string log;
  std::string log_tee;  // keel run's tee as /proc/<its pid>/fd/<fd>: the same pipe
  HostRole role;
  std::vector<std::string> rings;  // K=FD
};

int run(Args& a) {
  for (const auto& r : a.rings) {
    const auto eq = r.find('=');
    if (eq == std::string::npos) {
      std::cerr << "keel-host: --ring " << r << ": expected RING=FD\n";
      return 2;
    }
    a.role.ring_fds[std::stoul(r.substr(0, eq))] = std::stoi(r.substr(eq + 1));
  }
  auto set = keel::profile::load(a.profile);
  if (!set) {
    for (const auto& d : set.error()) std::cerr << "keel-host: " << d.str() << '\n';
    return 2;
  }
  auto planned = keel::plan::planProfiles(std::move(*set));
  if (!planned) {
    std::cerr << "keel-host: " << planned.error().message << '\n';
    return 2;
  }
  keel::engine::EngineOptions eo;
  for (const auto& text : a.sets) {
    auto s = keel::plan::parsePropertySetting(text);
    if (!s) {
      std::cerr << "keel-host: " << s.error().message << '\n';
      return 2;
    }
    eo.property_settings.push_back(std::move(*s));
  }
  if (auto r = keel::plan::applyPropertySettings(planned->plan, eo.property_settings); !r) {
    std::cerr << "keel-host: " << r.error().message << '\n';
    return 2;
  }
  auto opened = ProcessHost::open(planned->plan, a.role);
  if (!opened) {
    std::cerr << "keel-host: " << opened.error().message << '\n';
    return 2;
  }
  ProcessHost& host = **opened;
  host.setHeartbeat(keel::supervision::processHeartbeatNs(planned->plan, a.role.process) / 4);
  std::atomic<Engine*> running{nullptr};
  auto entered = host.enter([&running] {
    // keel run's unfinished line, if it died writing one, was written again first (ProcessHost).
    if (Engine* e = running.load(std::memory_order_acquire)) e->emergencyStop("keel run lost");
  });
  if (!entered) {
    std::cerr << "keel-host: " << entered.error().message << '\n';
    return 1;
  }
  auto failed = [&host](const std::string& why) {
    host.failed(why);
    ::_exit(1);
  };
  if (!a.inject.empty()) {
    auto scenario = keel::injection::loadScenario(a.inject);
    if (!scenario) {
      std::string why;
      for (const auto& d : scenario.error()) why += d.str() + '\n';
      failed(why);
    }
    eo.scenario = std::move(*scenario);
  }
  eo.log_path = a.log;
  eo.log_tee = a.log_tee;
  eo.host = &host;
  auto engine = Engine::create(std::move(*planned), std::move(eo));
  if (!engine) failed(engine.error().message);
  // From here keel run's death stops the actuators (once this host is active: ProcessHost).
  running.store(engine->get(), std::memory_order_release);
  if (auto r = (*engine)->start(); !r) {
    // Said first (keel run is waiting for it); then the components that initialized get their
    // onDestroy, as in keel run.
    host.failed(r.error().message);
    running.store(nullptr, std::memory_order_release);
    (*engine)->shutdown();
    std::cout.flush();
    ::_exit(1);
  }
  if (!host.stopRequested()) {
    host.serve([&] { (*engine)->emergencyStop("keel run"); }, [&] { (*engine)->clearEmergency("keel run"); });
  }
  running.store(nullptr, std::memory_order_release);
  (*engine)->shutdown();
  host.leave();
  std::cout.flush();
  ::_exit(0);  // the watcher threads sleep for the life of the process
}

}  // namespace

int main(int argc, char** argv) try {
  Args a;
  CLI::App app{"keel-host: a component process of keel run (started by keel run, not by hand)"};
  app.add_option("profile", a.profile)->required();
  app.add_option("--set", a.sets)->allow_extra_args(false);
  app.add_option("--inject", a.inject);
  app.add_option("--log", a.log);
  app.add_option("--log-tee", a.log_tee);
  app.add_option("--process", a.role.process)->required();
  app.add_option("--slot", a.role.slot)->required();
  app.add_option("--session-fd", a.role.session_fd)->required();
  app.add_option("--parent", a.role.parent)->required();
  app.add_option("--ring", a.rings)->allow_extra_args(false);
  app.add_flag("--standby", a.role.standby);
  app.add_flag("--respawn", a.role.respawn);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return run(a);
} catch (const std::exception& e) {
  std::cerr << "keel-host: " << e.what() << '\n';
  return 1;
}
