// opros_string_oarchive.h — keel's own OPRoS-compatible text output archive.
//
// `opros::archive::string_oarchive ar(&stream, mode);` writes every item as text: its type tag
// (the letters of opros_binary_format.h) and its value, then a space. Numbers are decimal, or
// hexadecimal with a 0x prefix when mode is 1 (floating point exactly, in either mode); a string
// is `S<length>:<bytes>`, a binary block `G<length>:<hex digits>`. string_iarchive reads both
// modes. The stream must outlive the archive. One thread at a time.
#pragma once

#include <charconv>
#include <cstddef>
#include <ostream>
#include <string>
#include <system_error>
#include <type_traits>

#include "opros_binary_format.h"
#include "opros_oarchive.h"

namespace opros {
namespace archive {

class string_oarchive : public oarchive {
 public:
  // mode 0: decimal numbers; mode 1: hexadecimal numbers.
  explicit string_oarchive(std::ostream* stream, int mode = 0) : stream_(stream), hex_(mode == 1) {
    if (stream_ == nullptr) throw archive_system_exception("opros archive: no output stream");
  }
  explicit string_oarchive(std::ostream& stream, int mode = 0) : string_oarchive(&stream, mode) {}

  oarchive& save(bool value) override { return item(detail::binary_tag<bool>(), value ? "1" : "0"); }
  oarchive& save(char value) override { return put(value); }
  oarchive& save(signed char value) override { return put(value); }
  oarchive& save(unsigned char value) override { return put(value); }
  oarchive& save(wchar_t value) override { return put(value); }
  oarchive& save(short value) override { return put(value); }
  oarchive& save(unsigned short value) override { return put(value); }
  oarchive& save(int value) override { return put(value); }
  oarchive& save(unsigned int value) override { return put(value); }
  oarchive& save(long value) override { return put(value); }
  oarchive& save(unsigned long value) override { return put(value); }
  oarchive& save(long long value) override { return put(value); }
  oarchive& save(unsigned long long value) override { return put(value); }
  oarchive& save(float value) override { return put(value); }
  oarchive& save(double value) override { return put(value); }
  oarchive& save(long double value) override { return put(value); }

  oarchive& save(const std::string& value) override {
    write(std::string(1, detail::kStringTag) + std::to_string(value.size()) + ":");
    write(value);
    return write(" ");
  }

  oarchive& save(const std::wstring& value) override {
    item(detail::kWideStringTag, std::to_string(value.size()));
    for (wchar_t c : value) put(c);
    return *this;
  }

  oarchive& save_binary(const char* data, long size) override {
    if (size < 0 || (size > 0 && data == nullptr)) {
      throw archive_format_exception("opros archive: save_binary of " + std::to_string(size) + " bytes from " +
                                     (data ? "a buffer" : "no buffer"));
    }
    static const char* const kHex = "0123456789abcdef";
    std::string text(1, detail::kBlockTag);
    text += std::to_string(size) + ":";
    for (long i = 0; i < size; ++i) {
      const auto byte = static_cast<unsigned char>(data[i]);
      text += kHex[byte >> 4];
      text += kHex[byte & 0xF];
    }
    return write(text + " ");
  }

  oarchive& write_size(std::size_t count) override { return item(detail::kSizeTag, std::to_string(count)); }

  oarchive& write_start_tag(const std::string&) override { return *this; }
  oarchive& write_end_tag(const std::string&) override { return *this; }

 private:
  template <typename T>
  oarchive& put(T value) {
    char digits[128];
    std::to_chars_result result{};
    if constexpr (std::is_integral_v<T>) {
      // Through the widest type of the same signedness: to_chars has no wchar_t overload.
      using Wide = std::conditional_t<std::is_signed_v<T>, long long, unsigned long long>;
      result = std::to_chars(digits, digits + sizeof digits, static_cast<Wide>(value), hex_ ? 16 : 10);
    } else if (hex_) {
      result = std::to_chars(digits, digits + sizeof digits, value, std::chars_format::hex);
    } else {
      result = std::to_chars(digits, digits + sizeof digits, value);
    }
    if (result.ec != std::errc()) throw archive_system_exception("opros archive: a number failed to format");
    std::string text(digits, result.ptr);
    const std::size_t sign = text[0] == '-' ? 1 : 0;
    if (hex_ && text[sign] != 'i' && text[sign] != 'n') text.insert(sign, "0x");  // not before inf or nan
    return item(detail::binary_tag<T>(), text);
  }

  oarchive& item(char tag, const std::string& text) { return write(std::string(1, tag) + text + " "); }

  oarchive& write(const std::string& text) {
    stream_->write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!*stream_) throw archive_system_exception("opros archive: the output stream failed");
    return *this;
  }

  std::ostream* stream_;
  bool hex_;
};

}  // namespace archive
}  // namespace opros
