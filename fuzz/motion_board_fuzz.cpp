// libFuzzer target for the motion board's byte protocol (robot/motion_board/protocol.hpp), the
// bytes the actuator reads from a serial line where a loose cable yields garbage. The input is
// fed to a Decoder in chunks whose sizes the input's first byte chooses; the rest of the input
// is also read as the harness's text fault command.
// Checked on every input, beyond no crash (ASan+UBSan): every frame decoded re-encodes to a
// frame the decoder accepts as the same frame; the decoder buffers at most one frame; every
// byte is either part of an accepted frame or counted as skipped (or still buffered); a parsed
// fault command prints as a command that parses to the same.
// Thread-safety: one input at a time, as libFuzzer calls it.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string_view>
#include <variant>

#include "robot/motion_board/protocol.hpp"

namespace {

using namespace keel::robot;

[[noreturn]] void broken(const char* what) {
  std::fprintf(stderr, "motion_board: %s\n", what);
  std::abort();
}

std::size_t frameBytes(const Frame& frame) { return encode(frame).size(); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 16;  // 1..16 bytes at a time, as reads come
  const std::span<const std::uint8_t> bytes(data + 1, size - 1);
  Decoder decoder;
  std::size_t accepted_bytes = 0;
  for (std::size_t at = 0; at < bytes.size(); at += chunk) {
    const auto frames = decoder.feed(bytes.subspan(at, std::min(chunk, bytes.size() - at)));
    for (const Frame& frame : frames) {
      accepted_bytes += frameBytes(frame);
      Decoder again;
      const auto encoded = encode(frame);
      const auto back = again.feed(encoded);
      if (back.size() != 1 || !(back[0] == frame)) broken("a decoded frame does not survive encode and decode");
    }
  }
  const DecoderStats& s = decoder.stats();
  if (accepted_bytes + s.skipped_bytes > bytes.size()) broken("more bytes accounted for than were fed");
  if (bytes.size() - accepted_bytes - s.skipped_bytes > 3 + 255 + 1) broken("more than one frame buffered");

  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (const auto fault = parseFaultCommand(text)) {
    const auto again = parseFaultCommand(toString(*fault));
    if (!again || !(*again == *fault)) broken("a fault command does not survive toString and parse");
  }
  return 0;
}
