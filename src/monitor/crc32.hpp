// CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, as zlib's crc32 and Python's
// zlib.crc32), the checksum MCAP uses for chunks, the data section and the summary. keel's own
// (a 256-entry table), so that the monitor needs no zlib.
// Thread-safety: a pure function over a constant table.
#pragma once

#include <cstdint>
#include <string_view>

namespace keel::monitor {

/// The CRC-32 of `bytes`, continuing from `running` (the CRC of the bytes before them; 0 to start),
/// so that crc32(b, crc32(a)) == crc32(a + b), as zlib's crc32(running, bytes, n).
std::uint32_t crc32(std::string_view bytes, std::uint32_t running = 0);

}  // namespace keel::monitor
