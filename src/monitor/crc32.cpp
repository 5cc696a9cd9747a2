#include "monitor/crc32.hpp"

#include <array>

namespace keel::monitor {
namespace {

constexpr std::uint32_t kPolynomial = 0xEDB88320U;  // 0x04C11DB7 bit-reversed: the reflected form

/// The CRC of each byte value alone, built at compile time: one lookup per byte instead of eight
/// shifts.
constexpr std::array<std::uint32_t, 256> makeTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t byte = 0; byte < table.size(); ++byte) {
    std::uint32_t c = byte;
    for (int bit = 0; bit < 8; ++bit) c = (c & 1U) ? (c >> 1) ^ kPolynomial : c >> 1;
    table[byte] = c;
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kTable = makeTable();

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t running) {
  // The register starts at all ones and the result is inverted; inverting `running` first is
  // what lets a CRC continue where an earlier call stopped.
  std::uint32_t c = ~running;
  for (char ch : bytes) c = kTable[(c ^ static_cast<unsigned char>(ch)) & 0xFFU] ^ (c >> 8);
  return ~c;
}

}  // namespace keel::monitor
