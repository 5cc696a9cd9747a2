// opros_binary_format.h — keel's own: the byte format of its OPRoS binary and raw archives.
//
// An item is a type tag (one byte; the raw archive omits it) and a payload: integers and
// characters in sizeof(T) little-endian bytes, bool as one byte 0 or 1, float and double as their
// IEEE bits (little-endian), long double as the host's bytes, a string or block as a 64-bit
// little-endian length and its bytes, a sequence count as a 64-bit little-endian number. The
// tags follow the Itanium C++ ABI's type letters. Header-only, stateless.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include "opros_archive_common.h"

namespace opros {
namespace archive {
namespace detail {

inline constexpr char kStringTag = 'S';
inline constexpr char kWideStringTag = 'W';
inline constexpr char kSizeTag = 'N';
inline constexpr char kBlockTag = 'G';

template <typename T>
constexpr char binary_tag() {
  if constexpr (std::is_same_v<T, bool>) return 'b';
  else if constexpr (std::is_same_v<T, char>) return 'c';
  else if constexpr (std::is_same_v<T, signed char>) return 'a';
  else if constexpr (std::is_same_v<T, unsigned char>) return 'h';
  else if constexpr (std::is_same_v<T, wchar_t>) return 'w';
  else if constexpr (std::is_same_v<T, short>) return 's';
  else if constexpr (std::is_same_v<T, unsigned short>) return 't';
  else if constexpr (std::is_same_v<T, int>) return 'i';
  else if constexpr (std::is_same_v<T, unsigned int>) return 'j';
  else if constexpr (std::is_same_v<T, long>) return 'l';
  else if constexpr (std::is_same_v<T, unsigned long>) return 'm';
  else if constexpr (std::is_same_v<T, long long>) return 'x';
  else if constexpr (std::is_same_v<T, unsigned long long>) return 'y';
  else if constexpr (std::is_same_v<T, float>) return 'f';
  else if constexpr (std::is_same_v<T, double>) return 'd';
  else if constexpr (std::is_same_v<T, long double>) return 'e';
  else static_assert(std::is_same_v<T, void>, "not an archive primitive");
}

// What a tag announces, for error messages.
inline std::string describe_binary_tag(char tag) {
  switch (tag) {
    case 'b': return "bool";
    case 'c': return "char";
    case 'a': return "signed char";
    case 'h': return "unsigned char";
    case 'w': return "wchar_t";
    case 's': return "short";
    case 't': return "unsigned short";
    case 'i': return "int";
    case 'j': return "unsigned int";
    case 'l': return "long";
    case 'm': return "unsigned long";
    case 'x': return "long long";
    case 'y': return "unsigned long long";
    case 'f': return "float";
    case 'd': return "double";
    case 'e': return "long double";
    case kStringTag: return "std::string";
    case kWideStringTag: return "std::wstring";
    case kSizeTag: return "a sequence count";
    case kBlockTag: return "a binary block";
    default: break;
  }
  static const char* const kHex = "0123456789abcdef";
  const auto byte = static_cast<unsigned char>(tag);
  return std::string("byte 0x") + kHex[byte >> 4] + kHex[byte & 0xF] +
         " (not an archive item: is this an opros binary archive?)";
}

template <typename T>
void encode_le(T value, unsigned char* out) {
  if constexpr (std::is_same_v<T, bool>) {
    out[0] = value ? 1 : 0;
  } else if constexpr (std::is_integral_v<T>) {
    using U = std::make_unsigned_t<T>;
    const auto bits = static_cast<U>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      out[i] = static_cast<unsigned char>((bits >> (8 * i)) & 0xFFu);
    }
  } else if constexpr (std::is_same_v<T, float>) {
    encode_le(std::bit_cast<std::uint32_t>(value), out);
  } else if constexpr (std::is_same_v<T, double>) {
    encode_le(std::bit_cast<std::uint64_t>(value), out);
  } else {
    static_assert(std::is_same_v<T, long double>);
    std::memcpy(out, &value, sizeof(T));
  }
}

template <typename T>
T decode_le(const unsigned char* in) {
  if constexpr (std::is_same_v<T, bool>) {
    if (in[0] > 1) {
      throw archive_format_exception("opros binary archive: a bool byte holds " + std::to_string(in[0]) +
                                     ", not 0 or 1");
    }
    return in[0] == 1;
  } else if constexpr (std::is_integral_v<T>) {
    using U = std::make_unsigned_t<T>;
    U bits = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      bits = static_cast<U>(bits | (static_cast<U>(in[i]) << (8 * i)));
    }
    return static_cast<T>(bits);
  } else if constexpr (std::is_same_v<T, float>) {
    return std::bit_cast<float>(decode_le<std::uint32_t>(in));
  } else if constexpr (std::is_same_v<T, double>) {
    return std::bit_cast<double>(decode_le<std::uint64_t>(in));
  } else {
    static_assert(std::is_same_v<T, long double>);
    T value;
    std::memcpy(&value, in, sizeof(T));
    return value;
  }
}

}  // namespace detail
}  // namespace archive
}  // namespace opros
