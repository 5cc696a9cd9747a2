#include "monitor/token.hpp"

#include <sys/random.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <system_error>

namespace keel::monitor {

Result<std::string> newToken() {
  std::array<std::uint8_t, 16> bits{};
  std::size_t have = 0;
  while (have < bits.size()) {
    const ssize_t n = ::getrandom(bits.data() + have, bits.size() - have, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return Error{"monitor: no random bits for the token: " + std::generic_category().message(errno)};
    have += static_cast<std::size_t>(n);
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string token;
  for (std::uint8_t b : bits) {
    token += kHex[b >> 4];
    token += kHex[b & 0xF];
  }
  return token;
}

bool tokenMatches(std::string_view token, std::string_view given) {
  if (token.empty() || given.size() != token.size()) return false;  // the length is not secret
  unsigned char diff = 0;
  for (std::size_t i = 0; i < token.size(); ++i) diff |= static_cast<unsigned char>(token[i] ^ given[i]);
  return diff == 0;
}

}  // namespace keel::monitor
