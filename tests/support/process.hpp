// Test support: runs a command (the keel CLI) and captures its exit status, stdout and stderr,
// or starts one; looks at processes through /proc.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
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

/// Starts argv with its stdout and stderr written to these files (fork + exec); its pid. A
/// child that cannot start exits 126 or 127.
inline pid_t startProcess(const std::vector<std::string>& argv, const std::string& out_path,
                          const std::string& err_path) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(out_path.c_str(), "w", stdout) || !freopen(err_path.c_str(), "w", stderr)) _exit(126);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

/// Runs argv; if `signal_after` > 0 sends SIGTERM after that long.
inline Ran runProcess(const std::vector<std::string>& argv,
                      std::chrono::milliseconds signal_after = std::chrono::milliseconds(0)) {
  auto dir = std::filesystem::temp_directory_path();
  static std::atomic<unsigned> runs{0};  // this process's runs: each its own files
  std::string tag = std::to_string(::getpid()) + "_" + std::to_string(runs++);
  std::string out_path = (dir / ("keel_out_" + tag)).string();
  std::string err_path = (dir / ("keel_err_" + tag)).string();
  const pid_t pid = startProcess(argv, out_path, err_path);
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

/// Process `pid`'s command line, an argument each (empty when it is gone or a zombie).
inline std::vector<std::string> commandLineOf(long pid) {
  const std::string cmdline = slurp("/proc/" + std::to_string(pid) + "/cmdline");
  std::vector<std::string> args;
  for (std::size_t at = 0, nul; at < cmdline.size(); at = nul + 1) {
    nul = cmdline.find('\0', at);
    if (nul == std::string::npos) nul = cmdline.size();
    args.push_back(cmdline.substr(at, nul - at));
  }
  return args;
}

/// The value after `flag` on process `pid`'s command line, or "".
inline std::string argumentOf(long pid, const std::string& flag) {
  const std::vector<std::string> args = commandLineOf(pid);
  for (std::size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == flag) return args[i + 1];
  return "";
}

/// The numbers of the processes in /proc.
inline std::vector<long> allProcesses() {
  std::vector<long> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") == std::string::npos) out.push_back(std::stol(name));
  }
  return out;
}

/// The processes other than this one whose command line has `text` in one of its arguments.
inline std::vector<long> processesMentioning(const std::string& text) {
  std::vector<long> out;
  for (long pid : allProcesses()) {
    if (pid == ::getpid()) continue;
    for (const auto& arg : commandLineOf(pid))
      if (arg.find(text) != std::string::npos) {
        out.push_back(pid);
        break;
      }
  }
  return out;
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
  for (long pid : allProcesses()) {
    const std::filesystem::path dir = "/proc/" + std::to_string(pid);
    std::ifstream stat(dir / "stat");
    std::string line;
    if (!std::getline(stat, line)) continue;
    const auto paren = line.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(line.substr(paren + 2));
    std::string state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid != parent) continue;
    std::string comm = slurp((dir / "comm").string());
    while (!comm.empty() && comm.back() == '\n') comm.pop_back();
    out.emplace_back(pid, comm);
  }
  return out;
}

}  // namespace keel::test
