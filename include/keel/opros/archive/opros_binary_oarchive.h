// opros_binary_oarchive.h — keel's own OPRoS-compatible binary output archive.
//
// `opros::archive::binary_oarchive ar(&stream);` (or `ar(stream)`) writes every item with a type
// tag (format: opros_binary_format.h), so that its reader detects a mismatched or foreign stream.
// The stream must outlive the archive. Write failures throw archive_system_exception. One thread
// at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

#include "opros_binary.h"
#include "opros_binary_format.h"
#include "opros_oarchive.h"

namespace opros {
namespace archive {
namespace detail {

// The binary writer; Tagged = false is the raw archive (no type tags).
template <bool Tagged>
class basic_binary_oarchive : public oarchive {
 public:
  explicit basic_binary_oarchive(std::ostream* stream) : stream_(stream) {
    if (stream_ == nullptr) throw archive_system_exception("opros archive: no output stream");
  }
  explicit basic_binary_oarchive(std::ostream& stream) : stream_(&stream) {}

  oarchive& save(bool value) override { return put(value); }
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
    write_tag(kStringTag);
    put_payload(static_cast<std::uint64_t>(value.size()));
    write_bytes(value.data(), value.size());
    return *this;
  }

  oarchive& save(const std::wstring& value) override {
    write_tag(kWideStringTag);
    put_payload(static_cast<std::uint64_t>(value.size()));
    for (wchar_t c : value) put_payload(c);
    return *this;
  }

  oarchive& save_binary(const char* data, long size) override {
    if (size < 0 || (size > 0 && data == nullptr)) {
      throw archive_format_exception("opros archive: save_binary of " + std::to_string(size) + " bytes from " +
                                     (data ? "a buffer" : "no buffer"));
    }
    write_tag(kBlockTag);
    put_payload(static_cast<std::uint64_t>(size));
    write_bytes(data, static_cast<std::size_t>(size));
    return *this;
  }

  oarchive& write_size(std::size_t count) override {
    write_tag(kSizeTag);
    put_payload(static_cast<std::uint64_t>(count));
    return *this;
  }

  oarchive& write_start_tag(const std::string&) override { return *this; }
  oarchive& write_end_tag(const std::string&) override { return *this; }

 private:
  template <typename T>
  oarchive& put(T value) {
    write_tag(binary_tag<T>());
    put_payload(value);
    return *this;
  }

  template <typename T>
  void put_payload(T value) {
    unsigned char bytes[sizeof(T)];
    encode_le(value, bytes);
    write_bytes(bytes, sizeof(T));
  }

  void write_tag(char tag) {
    if constexpr (Tagged) write_bytes(&tag, 1);
  }

  void write_bytes(const void* data, std::size_t size) {
    if (size == 0) return;
    stream_->write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!*stream_) throw archive_system_exception("opros archive: the output stream failed");
  }

  std::ostream* stream_;
};

}  // namespace detail

class binary_oarchive : public detail::basic_binary_oarchive<true> {
 public:
  using basic_binary_oarchive::basic_binary_oarchive;
};

}  // namespace archive
}  // namespace opros
