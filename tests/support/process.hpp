// Test support: runs a command (the keel CLI) and captures its exit status, stdout and stderr;
// looks at processes through /proc.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace keel::test {

struct Ran {
  int status = -1;  // exit status, or 128 + signal
  std::string out;
  std::string err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs argv; if `signal_after` > 0 sends SIGTERM after that long.
inline Ran runProcess(const std::vector<std::string>& argv,
                      std::chrono::milliseconds signal_after = std::chrono::milliseconds(0)) {
  auto dir = std::filesystem::temp_directory_path();
  std::string tag = std::to_string(::getpid()) + "_" + std::to_string(std::rand());
  std::string out_path = (dir / ("keel_out_" + tag)).string();
  std::string err_path = (dir / ("keel_err_" + tag)).string();
  pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(out_path.c_str(), "w", stdout) || !freopen(err_path.c_str(), "w", stderr)) _exit(126);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  if (signal_after.count() > 0) {
    std::this_thread::sleep_for(signal_after);
    kill(pid, SIGTERM);
  }
  int st = 0;
  waitpid(pid, &st, 0);
  Ran r;
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  r.out = slurp(out_path);
  r.err = slurp(err_path);
  std::filesystem::remove(out_path);
  std::filesystem::remove(err_path);
  return r;
}

/// Whether process `pid` has ended: no such process, or a zombie no one reaped yet.
inline bool processGone(long pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  if (!stat) return true;
  std::string line;
  std::getline(stat, line);
  const auto paren = line.rfind(')');
  return paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] == 'Z';
}

/// The processes whose parent is `parent`, with their command names (/proc/PID/comm).
inline std::vector<std::pair<long, std::string>> childrenOf(long parent) {
  std::vector<std::pair<long, std::string>> out;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const auto paren = line.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(line.substr(paren + 2));
    std::string state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid != parent) continue;
    std::string comm = slurp((entry.path() / "comm").string());
    while (!comm.empty() && comm.back() == '\n') comm.pop_back();
    out.emplace_back(std::stol(name), comm);
  }
  return out;
}

}  // namespace keel::test
