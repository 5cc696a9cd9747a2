#include "soak/resources.hpp"

#include <malloc.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#if defined(KEEL_SOAK_UNDER_ASAN)
// ASan's runtime (its header, sanitizer/allocator_interface.h, comes with clang, not with g++).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace keel::soak {

Usage usageNow(bool trim) {
  if (trim) ::malloc_trim(0);
  Usage u;
  std::ifstream statm("/proc/self/statm");
  std::uint64_t size = 0, resident = 0;
  if (statm >> size >> resident) u.rss_bytes = resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
#if defined(KEEL_SOAK_UNDER_ASAN)
  u.heap_bytes = __sanitizer_get_current_allocated_bytes();
#else
  const struct mallinfo2 m = ::mallinfo2();
  u.heap_bytes = m.uordblks + m.hblkhd;
#endif
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++u.fds;
  if (u.fds > 0) --u.fds;  // the directory iterator's own
  return u;
}

std::vector<std::string> childrenNow() {
  std::vector<std::string> children;
  const std::string self = std::to_string(::getpid());
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc", ec); !ec && it != std::filesystem::directory_iterator();
       it.increment(ec)) {
    const std::string pid = it->path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(it->path() / "stat");
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    // pid (comm) state ppid ...: comm may hold spaces and parentheses; it ends at the last ')'.
    const std::size_t close = text.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(text.substr(close + 1));
    std::string state, ppid;
    rest >> state >> ppid;
    if (ppid != self) continue;
    const std::size_t open = text.find('(');
    children.push_back(pid + " " + text.substr(open, close - open + 1) +
                       (state == "Z" ? " (zombie: never waited for)" : ""));
  }
  return children;
}

}  // namespace keel::soak
