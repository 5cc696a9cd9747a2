// opros_archive_common.h — keel's own OPRoS-compatible version of what every OPRoS archive shares.
//
// The archive base class, the archive exceptions (all std::exception, with a message that says
// what was being read or written and where), named values (`opros::nvp`, OPROS_SERIALIZATION_NVP),
// and `opros::archive::access`, which a user type befriends so that the archive can call its
// save/load members. Header-only; nothing here has state shared between threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "opros_type_traits.h"

#define OPROS_SERIALIZATION_VERSION 1

namespace opros {
namespace archive {

class oarchive;
class iarchive;

// The root of OPRoS's archives.
class archive {
 public:
  virtual ~archive() = default;
};

// Every archive error; the subclasses are OPRoS's names.
class archive_exception : public std::runtime_error {
 public:
  explicit archive_exception(const std::string& message) : std::runtime_error(message) {}
};

// The stream holds another type than the one being read.
class archive_type_exception : public archive_exception {
 public:
  archive_type_exception() : archive_exception("opros archive: type mismatch") {}
  explicit archive_type_exception(const std::string& message) : archive_exception(message) {}
};

// A fixed-size array was read from a sequence of another length.
class archive_array_size_exception : public archive_exception {
 public:
  archive_array_size_exception() : archive_exception("opros archive: array size mismatch") {}
  explicit archive_array_size_exception(const std::string& message) : archive_exception(message) {}
};

// The stream itself failed (no stream, a write that did not happen).
class archive_system_exception : public archive_exception {
 public:
  archive_system_exception() : archive_exception("opros archive: stream error") {}
  explicit archive_system_exception(const std::string& message) : archive_exception(message) {}
};

// The stream is malformed or ends early.
class archive_format_exception : public archive_exception {
 public:
  archive_format_exception() : archive_exception("opros archive: format error") {}
  explicit archive_format_exception(const std::string& message) : archive_exception(message) {}
};

// What a user type befriends (`friend class opros::archive::access;`) so that the archive can
// call its `save(oarchive&, const unsigned int)` and `load(iarchive&, const unsigned int)`,
// public or not. A `template <class Ar> void serialize(Ar&, const unsigned int)` member works too.
class access {
 public:
  template <typename T>
  static void save(oarchive& ar, T& t) {
    t.save(ar, OPROS_SERIALIZATION_VERSION);
  }

  template <typename T>
  static void load(iarchive& ar, T& t) {
    t.load(ar, OPROS_SERIALIZATION_VERSION);
  }

  template <typename Archive, typename T>
  static void serialize(Archive& ar, T& t) {
    t.serialize(ar, OPROS_SERIALIZATION_VERSION);
  }

  // Checked here, so that a befriended private member counts.
  template <typename T>
  static constexpr bool can_save = requires(T& t, oarchive& ar) {
    t.save(ar, 1u);
  };
  template <typename T>
  static constexpr bool can_load = requires(T& t, iarchive& ar) {
    t.load(ar, 1u);
  };
  template <typename T, typename Archive>
  static constexpr bool can_serialize = requires(T& t, Archive& ar) {
    t.serialize(ar, 1u);
  };
};

}  // namespace archive

// A value with a name, for archives that write names (keel's binary archive does not).
class nvp_base {};

template <typename Type>
class nvp : public nvp_base {
 public:
  nvp(const std::string& name, Type& data) : name_(name), data_(data) {}

  const std::string& getName() const { return name_; }
  Type& getData() const { return data_; }

 private:
  std::string name_;
  Type& data_;
};

template <typename T>
inline nvp<T> makenvp(const std::string& name, T& value) {
  return nvp<T>(name, value);
}

}  // namespace opros

#define OPROS_SERIALIZATION_NVP(a) ::opros::makenvp(#a, a)
#define OPROS_SERIALIZATION_MAKE_NVP(a, b) ::opros::makenvp(#a, b)

// OPRoS's test for a type with both save and load members.
template <typename Type>
struct has_opros_serialization
    : std::bool_constant<opros::archive::access::can_save<std::remove_cvref_t<std::remove_pointer_t<Type>>> &&
                         opros::archive::access::can_load<std::remove_cvref_t<std::remove_pointer_t<Type>>>> {};

inline bool is_little_endian() {
  const unsigned short probe = 1;
  return *reinterpret_cast<const unsigned char*>(&probe) == 1;
}

// Reverses the sz bytes at p.
inline void change_endian(unsigned char* p, int sz) {
  if (p != nullptr && sz > 1) std::reverse(p, p + sz);
}
