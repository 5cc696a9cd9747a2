// opros_string_iarchive.h — keel's own OPRoS-compatible text input archive.
//
// `opros::archive::string_iarchive ar(&stream);` reads what string_oarchive wrote, in either of
// its modes. A stream that ends early, a malformed number or a number out of the target's range
// throws archive_format_exception; an item of another type archive_type_exception. The stream
// must outlive the archive. One thread at a time.
#pragma once

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstddef>
#include <istream>
#include <limits>
#include <memory>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

#include "opros_binary_format.h"
#include "opros_iarchive.h"

namespace opros {
namespace archive {

class string_iarchive : public iarchive {
 public:
  explicit string_iarchive(std::istream* stream) : stream_(stream) {
    if (stream_ == nullptr) throw archive_system_exception("opros archive: no input stream");
  }
  explicit string_iarchive(std::istream& stream) : string_iarchive(&stream) {}

  iarchive& load(bool& value) override {
    expect_tag(detail::binary_tag<bool>(), "bool");
    const std::string text = token("bool");
    if (text != "0" && text != "1") fail("bool", "'" + text + "' is not 0 or 1");
    value = text == "1";
    return *this;
  }
  iarchive& load(char& value) override { return get(value, "char"); }
  iarchive& load(signed char& value) override { return get(value, "signed char"); }
  iarchive& load(unsigned char& value) override { return get(value, "unsigned char"); }
  iarchive& load(wchar_t& value) override { return get(value, "wchar_t"); }
  iarchive& load(short& value) override { return get(value, "short"); }
  iarchive& load(unsigned short& value) override { return get(value, "unsigned short"); }
  iarchive& load(int& value) override { return get(value, "int"); }
  iarchive& load(unsigned int& value) override { return get(value, "unsigned int"); }
  iarchive& load(long& value) override { return get(value, "long"); }
  iarchive& load(unsigned long& value) override { return get(value, "unsigned long"); }
  iarchive& load(long long& value) override { return get(value, "long long"); }
  iarchive& load(unsigned long long& value) override { return get(value, "unsigned long long"); }
  iarchive& load(float& value) override { return get(value, "float"); }
  iarchive& load(double& value) override { return get(value, "double"); }
  iarchive& load(long double& value) override { return get(value, "long double"); }

  iarchive& load(std::string& value) override {
    expect_tag(detail::kStringTag, "std::string");
    const std::size_t length = counted_prefix("std::string");
    std::string result;
    while (result.size() < length) {  // in chunks: a corrupt length fails at the stream's end
      const std::size_t old_size = result.size();
      const std::size_t chunk = std::min(kChunk, length - old_size);
      result.resize(old_size + chunk);
      read_exactly(result.data() + old_size, chunk, "std::string");
    }
    value = std::move(result);
    return *this;
  }

  iarchive& load(std::wstring& value) override {
    expect_tag(detail::kWideStringTag, "std::wstring");
    const std::size_t length = parse<std::size_t>(token("std::wstring"), "std::wstring");
    std::wstring result;
    for (std::size_t i = 0; i < length; ++i) {
      wchar_t c = 0;
      load(c);
      result.push_back(c);
    }
    value = std::move(result);
    return *this;
  }

  iarchive& load_binary(char** data, long& size) override {
    if (data == nullptr) throw archive_system_exception("opros archive: load_binary without a target");
    expect_tag(detail::kBlockTag, "a binary block");
    const std::size_t length = counted_prefix("a binary block");
    if (length > static_cast<std::size_t>(std::numeric_limits<long>::max())) {
      fail("a binary block", "its length " + std::to_string(length) + " is too large");
    }
    if (*data != nullptr && (size < 0 || length > static_cast<std::size_t>(size))) {
      throw archive_array_size_exception("opros archive: a binary block of " + std::to_string(length) +
                                         " bytes does not fit in " + std::to_string(size));
    }
    std::vector<char> bytes;
    while (bytes.size() < length) {
      char pair[2];
      read_exactly(pair, 2, "a binary block");
      bytes.push_back(static_cast<char>(hex_digit(pair[0]) * 16 + hex_digit(pair[1])));
    }
    if (*data == nullptr) {
      auto block = std::make_unique<char[]>(length == 0 ? 1 : length);
      std::copy(bytes.begin(), bytes.end(), block.get());
      *data = block.release();
    } else {
      std::copy(bytes.begin(), bytes.end(), *data);
    }
    size = static_cast<long>(length);
    return *this;
  }

  std::size_t read_size() override {
    expect_tag(detail::kSizeTag, "a sequence count");
    return parse<std::size_t>(token("a sequence count"), "a sequence count");
  }

  iarchive& read_start_tag(const std::string&) override { return *this; }
  iarchive& read_end_tag(const std::string&) override { return *this; }

 private:
  static constexpr std::size_t kChunk = std::size_t{1} << 16;
  static constexpr std::size_t kMaxToken = 128;

  template <typename T>
  iarchive& get(T& value, const char* what) {
    expect_tag(detail::binary_tag<T>(), what);
    value = parse<T>(token(what), what);
    return *this;
  }

  // Parses a whole token as T, decimal or 0x-prefixed hexadecimal.
  template <typename T>
  T parse(const std::string& text, const char* what) {
    const bool negative = !text.empty() && text[0] == '-';
    const std::size_t digits_at = negative ? 1 : 0;
    const bool hex = text.compare(digits_at, 2, "0x") == 0;
    std::string digits = text;
    if (hex) digits.erase(digits_at, 2);
    const char* first = digits.data();
    const char* last = digits.data() + digits.size();
    std::from_chars_result result{};
    T value{};
    if constexpr (std::is_integral_v<T>) {
      using Wide = std::conditional_t<std::is_signed_v<T>, long long, unsigned long long>;
      Wide wide{};
      result = std::from_chars(first, last, wide, hex ? 16 : 10);
      if (result.ec == std::errc() && (wide < static_cast<Wide>(std::numeric_limits<T>::min()) ||
                                       wide > static_cast<Wide>(std::numeric_limits<T>::max()))) {
        result.ec = std::errc::result_out_of_range;
      }
      value = static_cast<T>(wide);
    } else {
      result = std::from_chars(first, last, value, hex ? std::chars_format::hex : std::chars_format::general);
    }
    if (result.ec == std::errc::result_out_of_range) fail(what, "'" + text + "' is out of range");
    if (result.ec != std::errc() || result.ptr != last || digits.empty()) {
      fail(what, "'" + text + "' is not a number");
    }
    return value;
  }

  // "<decimal length>:" before a string's bytes.
  std::size_t counted_prefix(const char* what) {
    const std::size_t length = parse<std::size_t>(token(what), what);
    if (next(what) != ':') fail(what, "its length is not followed by ':'");
    return length;
  }

  void expect_tag(char expected, const char* what) {
    int c = next(what);
    while (std::isspace(c)) c = next(what);
    if (static_cast<char>(c) != expected) {
      throw archive_type_exception("opros string archive: expected " + std::string(what) + " at character " +
                                   std::to_string(position_ - 1) + ", found " +
                                   detail::describe_binary_tag(static_cast<char>(c)));
    }
  }

  // Characters up to the next space or ':' (not consumed) or the end of the stream.
  std::string token(const char* what) {
    std::string text;
    for (;;) {
      const int c = stream_->peek();
      if (c == std::char_traits<char>::eof() || std::isspace(c) || c == ':') break;
      if (text.size() == kMaxToken) fail(what, "a number longer than " + std::to_string(kMaxToken));
      text.push_back(static_cast<char>(next(what)));
    }
    if (text.empty()) fail(what, "no value");
    return text;
  }

  int next(const char* what) {
    const int c = stream_->get();
    if (c == std::char_traits<char>::eof()) {
      throw archive_format_exception("opros archive: the stream ends at character " + std::to_string(position_) +
                                     " while reading " + what);
    }
    ++position_;
    return c;
  }

  void read_exactly(char* out, std::size_t size, const char* what) {
    stream_->read(out, static_cast<std::streamsize>(size));
    const auto got = static_cast<std::size_t>(stream_->gcount());
    position_ += got;
    if (got != size) {
      throw archive_format_exception("opros archive: the stream ends at character " + std::to_string(position_) +
                                     " while reading " + what);
    }
  }

  int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    fail("a binary block", std::string("'") + c + "' is not a hexadecimal digit");
  }

  [[noreturn]] void fail(const char* what, const std::string& problem) {
    throw archive_format_exception("opros string archive: reading " + std::string(what) + " before character " +
                                   std::to_string(position_) + ": " + problem);
  }

  std::istream* stream_;
  std::size_t position_ = 0;
};

}  // namespace archive
}  // namespace opros
