// opros_binary_iarchive.h — keel's own OPRoS-compatible binary input archive.
//
// `opros::archive::binary_iarchive ar(&stream);` reads what binary_oarchive wrote. Every read is
// checked: a stream that ends early throws archive_format_exception, an item of another type
// archive_type_exception, both naming the byte offset; a length in the stream is never trusted
// for an allocation beyond what was actually read. The stream must outlive the archive. One
// thread at a time.
#pragma once

#include <algorithm>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "opros_binary.h"
#include "opros_binary_format.h"
#include "opros_iarchive.h"

namespace opros {
namespace archive {
namespace detail {

// The binary reader; Tagged = false is the raw archive (no type tags to check).
template <bool Tagged>
class basic_binary_iarchive : public iarchive {
 public:
  explicit basic_binary_iarchive(std::istream* stream) : stream_(stream) {
    if (stream_ == nullptr) throw archive_system_exception("opros archive: no input stream");
  }
  explicit basic_binary_iarchive(std::istream& stream) : stream_(&stream) {}

  iarchive& load(bool& value) override { return get(value, "bool"); }
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
    expect_tag(kStringTag, "std::string");
    const std::size_t length = get_length("std::string");
    std::string result;
    while (result.size() < length) {  // in chunks: a corrupt length fails at the stream's end
      const std::size_t old_size = result.size();
      const std::size_t chunk = std::min(kChunk, length - old_size);
      result.resize(old_size + chunk);
      read_bytes(result.data() + old_size, chunk, "std::string");
    }
    value = std::move(result);
    return *this;
  }

  iarchive& load(std::wstring& value) override {
    expect_tag(kWideStringTag, "std::wstring");
    const std::size_t length = get_length("std::wstring");
    std::wstring result;
    for (std::size_t i = 0; i < length; ++i) result.push_back(get_payload<wchar_t>("std::wstring"));
    value = std::move(result);
    return *this;
  }

  iarchive& load_binary(char** data, long& size) override {
    if (data == nullptr) throw archive_system_exception("opros archive: load_binary without a target");
    expect_tag(kBlockTag, "a binary block");
    const std::size_t length = get_length("a binary block");
    if (length > static_cast<std::size_t>(std::numeric_limits<long>::max())) {
      throw archive_format_exception("opros archive: a binary block of " + std::to_string(length) + " bytes");
    }
    if (*data != nullptr) {
      if (size < 0 || length > static_cast<std::size_t>(size)) {
        throw archive_array_size_exception("opros archive: a binary block of " + std::to_string(length) +
                                           " bytes does not fit in " + std::to_string(size));
      }
      read_bytes(*data, length, "a binary block");
    } else {
      std::vector<char> bytes;
      while (bytes.size() < length) {
        const std::size_t old_size = bytes.size();
        const std::size_t chunk = std::min(kChunk, length - old_size);
        bytes.resize(old_size + chunk);
        read_bytes(bytes.data() + old_size, chunk, "a binary block");
      }
      auto block = std::make_unique<char[]>(length == 0 ? 1 : length);
      std::copy(bytes.begin(), bytes.end(), block.get());
      *data = block.release();
    }
    size = static_cast<long>(length);
    return *this;
  }

  std::size_t read_size() override {
    expect_tag(kSizeTag, "a sequence count");
    return get_length("a sequence count");
  }

  iarchive& read_start_tag(const std::string&) override { return *this; }
  iarchive& read_end_tag(const std::string&) override { return *this; }

  // Bytes consumed so far.
  std::size_t position() const { return position_; }

 private:
  static constexpr std::size_t kChunk = std::size_t{1} << 16;

  template <typename T>
  iarchive& get(T& value, const char* what) {
    expect_tag(binary_tag<T>(), what);
    value = get_payload<T>(what);
    return *this;
  }

  template <typename T>
  T get_payload(const char* what) {
    unsigned char bytes[sizeof(T)];
    read_bytes(bytes, sizeof(T), what);
    return decode_le<T>(bytes);
  }

  std::size_t get_length(const char* what) {
    const auto length = get_payload<std::uint64_t>(what);
    if (length > std::numeric_limits<std::size_t>::max()) {
      throw archive_format_exception("opros archive: a length of " + std::to_string(length) + " for " + what);
    }
    return static_cast<std::size_t>(length);
  }

  void expect_tag(char expected, const char* what) {
    if constexpr (Tagged) {
      const std::size_t at = position_;
      char found = 0;
      read_bytes(&found, 1, what);
      if (found != expected) {
        throw archive_type_exception("opros binary archive: expected " + std::string(what) + " at byte " +
                                     std::to_string(at) + ", found " + describe_binary_tag(found));
      }
    }
  }

  void read_bytes(void* out, std::size_t size, const char* what) {
    if (size == 0) return;
    stream_->read(static_cast<char*>(out), static_cast<std::streamsize>(size));
    const auto got = static_cast<std::size_t>(stream_->gcount());
    position_ += got;
    if (got != size) {
      throw archive_format_exception("opros archive: the stream ends at byte " + std::to_string(position_) +
                                     " while reading " + what + " (" + std::to_string(size - got) +
                                     " more bytes needed)");
    }
  }

  std::istream* stream_;
  std::size_t position_ = 0;
};

}  // namespace detail

class binary_iarchive : public detail::basic_binary_iarchive<true> {
 public:
  using basic_binary_iarchive::basic_binary_iarchive;
};

}  // namespace archive
}  // namespace opros
