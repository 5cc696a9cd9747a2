// The pieces every generated message conversion (keel/msg/<pkg>/msg/detail/<name>__dds.hpp,
// written by cmake/keel_msggen.py) is made of: a keel::msg field to its field of the C sample
// CycloneDDS's idlc generates, and back. To DDS borrows what it can (a string's characters, a
// vector of numbers' elements: the C sample points into the C++ value, which must outlive the
// write); what it cannot borrow (a std::vector<bool>'s bits, an array of string pointers, a
// bounded string's inline characters) it builds in the DdsScratch. From DDS copies. Bounded
// strings and bounded sequences longer than their bound are truncated to it.
// Templates over idlc's sequence structs ({_maximum, _length, _buffer, _release}): no CycloneDDS
// header is needed here. Authors never name this header. Reentrant.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "keel/detail/dds_type.hpp"

namespace keel::msg::dds::detail {

/// Elements of `v` that go on the wire: all of them, or `bound` (> 0) if there are more.
template <class T>
std::uint32_t wireLength(const std::vector<T>& v, std::uint32_t bound) {
  std::size_t n = v.size();
  if (bound != 0 && n > bound) n = bound;
  return static_cast<std::uint32_t>(std::min<std::size_t>(n, UINT32_MAX));
}

template <class Seq, class T>
void setSequence(Seq& seq, T* buffer, std::uint32_t length) {
  seq._buffer = buffer;
  seq._length = length;
  seq._maximum = length;
  seq._release = false;  // never freed by CycloneDDS: borrowed or scratch
}

// --- strings ---------------------------------------------------------------------------------

/// A `string` field: the C sample points at the C++ string's characters.
inline char* borrowString(const std::string& s) { return const_cast<char*>(s.c_str()); }

inline void copyString(const char* s, std::string& out) {
  if (s != nullptr) {
    out.assign(s);
  } else {
    out.clear();
  }
}

/// A `string<=N` field: idlc makes it `char[N + 1]` inline; copied, truncated to N bytes.
template <std::size_t M>
void copyBounded(const std::string& s, char (&out)[M]) {
  const std::size_t n = std::min(s.size(), M - 1);
  std::memcpy(out, s.data(), n);
  out[n] = '\0';
}

template <std::size_t M>
void copyBounded(const char (&in)[M], std::string& out) {
  const void* end = std::memchr(in, '\0', M);
  out.assign(in, end != nullptr ? static_cast<const char*>(end) : in + M);
}

// --- fixed arrays (T[N]: std::array<T, N> ↔ T[N]) -------------------------------------------

template <class T, std::size_t N>
void copyArray(const std::array<T, N>& v, T (&out)[N]) {
  std::copy(v.begin(), v.end(), out);
}

template <class T, std::size_t N>
void copyArray(const T (&in)[N], std::array<T, N>& out) {
  std::copy(in, in + N, out.begin());
}

template <std::size_t N>
void borrowStrings(const std::array<std::string, N>& v, char* (&out)[N]) {
  for (std::size_t i = 0; i < N; ++i) out[i] = borrowString(v[i]);
}

template <std::size_t N>
void copyStrings(char* const (&in)[N], std::array<std::string, N>& out) {
  for (std::size_t i = 0; i < N; ++i) copyString(in[i], out[i]);
}

template <std::size_t N, std::size_t M>
void copyBoundedStrings(const std::array<std::string, N>& v, char (&out)[N][M]) {
  for (std::size_t i = 0; i < N; ++i) copyBounded(v[i], out[i]);
}

template <std::size_t N, std::size_t M>
void copyBoundedStrings(const char (&in)[N][M], std::array<std::string, N>& out) {
  for (std::size_t i = 0; i < N; ++i) copyBounded(in[i], out[i]);
}

// --- sequences (T[], T[<=N]: std::vector<T> ↔ idlc's sequence struct) ------------------------

/// Numbers: the sequence's buffer is the vector's own storage.
template <class Seq, class T>
void borrowSequence(const std::vector<T>& v, Seq& seq, std::uint32_t bound) {
  static_assert(std::is_same_v<std::remove_pointer_t<decltype(seq._buffer)>, T>,
                "the C sequence's element type must be the vector's");
  setSequence(seq, const_cast<T*>(v.data()), wireLength(v, bound));
}

/// A zeroed buffer in `scratch` for the sequence's elements (nested messages, strings, bools),
/// which the caller fills; returns it.
template <class Seq, class T>
auto allocSequence(const std::vector<T>& v, Seq& seq, keel::detail::DdsScratch& scratch, std::uint32_t bound) {
  using Element = std::remove_pointer_t<decltype(seq._buffer)>;
  const std::uint32_t n = wireLength(v, bound);
  Element* buffer = scratch.make<Element>(n);
  setSequence(seq, buffer, n);
  return buffer;
}

/// std::vector<bool> has no contiguous bools to lend: copied into the scratch.
template <class Seq>
void copySequence(const std::vector<bool>& v, Seq& seq, keel::detail::DdsScratch& scratch, std::uint32_t bound) {
  bool* buffer = allocSequence(v, seq, scratch, bound);
  for (std::uint32_t i = 0; i < seq._length; ++i) buffer[i] = v[i];
}

template <class Seq>
void borrowStrings(const std::vector<std::string>& v, Seq& seq, keel::detail::DdsScratch& scratch,
                   std::uint32_t bound) {
  char** buffer = allocSequence(v, seq, scratch, bound);
  for (std::uint32_t i = 0; i < seq._length; ++i) buffer[i] = borrowString(v[i]);
}

template <class Seq>
void copyBoundedStrings(const std::vector<std::string>& v, Seq& seq, keel::detail::DdsScratch& scratch,
                        std::uint32_t bound) {
  auto* buffer = allocSequence(v, seq, scratch, bound);
  for (std::uint32_t i = 0; i < seq._length; ++i) copyBounded(v[i], buffer[i]);
}

/// Numbers and bools from DDS.
template <class Seq, class T>
void copySequence(const Seq& seq, std::vector<T>& out) {
  if (seq._length == 0) {
    out.clear();
    return;
  }
  out.assign(seq._buffer, seq._buffer + seq._length);
}

template <class Seq>
void copyStrings(const Seq& seq, std::vector<std::string>& out) {
  out.resize(seq._length);
  for (std::uint32_t i = 0; i < seq._length; ++i) copyString(seq._buffer[i], out[i]);
}

template <class Seq>
void copyBoundedStrings(const Seq& seq, std::vector<std::string>& out) {
  out.resize(seq._length);
  for (std::uint32_t i = 0; i < seq._length; ++i) copyBounded(seq._buffer[i], out[i]);
}

}  // namespace keel::msg::dds::detail
