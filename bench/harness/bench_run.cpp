#include "bench_run.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <new>

namespace keel::bench {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using keel_bench::BenchPage;

std::string benchComponentXml(const std::string& library, const std::string& name, const std::string& semantics,
                              const std::string& ports, const std::string& page, const std::string& properties) {
  return fmt::format(R"(<?xml version="1.0" encoding="UTF-8"?>
<component_profile>
  <name>{}</name>
  <execution_environment><library_name>{}</library_name></execution_environment>
  <execution_semantics>{}</execution_semantics>
  <properties><property name="page" type="string">{}</property>{}</properties>
  <ports>{}</ports>
</component_profile>
)",
                     name, library, semantics, page, properties, ports);
}

std::string schedXml(bool fifo) {
  return fifo ? fmt::format("<priority>{}</priority><policy>fifo</policy>", kFifoPriority) : "";
}

SharedPage::SharedPage() : path_(fmt::format("/dev/shm/keel-bench-page.{}.{}", ::getpid(), counter_++)) {}

SharedPage::~SharedPage() {
  if (page_) ::munmap(page_, sizeof(BenchPage));
  ::unlink(path_.c_str());
}

std::string SharedPage::create() {
  if (page_) {
    ::munmap(page_, sizeof(BenchPage));
    page_ = nullptr;
  }
  const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0 || ::ftruncate(fd, sizeof(BenchPage)) != 0) {
    if (fd >= 0) ::close(fd);
    return "cannot create " + path_;
  }
  void* p = ::mmap(nullptr, sizeof(BenchPage), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  if (p == MAP_FAILED) return "cannot map " + path_;
  page_ = new (p) BenchPage;
  return {};
}

std::vector<nlohmann::json> LogTail::newRecords() {
  std::vector<nlohmann::json> out;
  std::ifstream in(path_);
  if (!in) return out;
  in.seekg(static_cast<std::streamoff>(read_));
  std::string line;
  while (std::getline(in, line) && !in.eof()) {
    read_ += line.size() + 1;
    auto r = nlohmann::json::parse(line, nullptr, false);
    if (!r.is_discarded()) out.push_back(std::move(r));
  }
  return out;
}

BenchRun::BenchRun(const Paths& paths, const std::string& prefix) : paths_(paths), dir_(prefix) {}

BenchRun::~BenchRun() {
  proc_.reset();  // killed and reaped if still there: its hosts follow (no orphans)
}

std::string BenchRun::start(const std::vector<std::pair<std::string, std::string>>& files, const std::string& package,
                            const std::vector<std::string>& launcher, std::vector<EnvChange> env) {
  if (dir_.path().empty()) return "mkdtemp failed";
  if (auto e = page_.create(); !e.empty()) return e;
  for (const auto& [name, text] : files) std::ofstream(dir_.path() + "/" + name) << text;
  log_.reset(dir_.path() + "/fault.jsonl");
  out_path_ = dir_.path() + "/keel-run.out";
  const int out = ::open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  env.push_back({"KEEL_COMPONENT_PATH", paths_.components});
  std::vector<std::string> argv = launcher;
  for (std::string a :
       {paths_.bin + "/keel", std::string("run"), dir_.path() + "/" + package, std::string("--duration"),
        std::string("86400"), std::string("--log"), dir_.path() + "/fault.jsonl"})
    argv.push_back(std::move(a));
  auto spawned = Process::spawn(argv, {.out = out, .err = out}, false, true, env);
  ::close(out);
  if (!spawned) return "keel run: " + spawned.error().message;
  proc_.emplace(std::move(*spawned));
  return {};
}

std::string BenchRun::failure(const std::string& what) const {
  std::ifstream in(out_path_);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return what + (last.empty() ? "" : ": keel run said: " + last);
}

std::size_t BenchRun::hostPhases(const std::string& phase) {
  for (auto& r : newRecords()) {
    const std::string event = r.value("event", "");
    if (event == "host") ++phases_[r.value("phase", "")];
    if (event == "recovered") recovered_ns_.push_back(static_cast<std::int64_t>(r.value("latency_us", 0.0) * 1000));
  }
  return phases_[phase];
}

void BenchRun::signal(int sig) const {
  if (proc_) proc_->signal(sig);
}

void BenchRun::stop() {
  if (!proc_) return;
  proc_->signal(SIGTERM);
  proc_->waitUntil(Clock::now() + 10s);
  proc_.reset();
}

}  // namespace keel::bench
