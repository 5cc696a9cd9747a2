// ApiTypes.h — keel's own, from-scratch OPRoS-compatible version of the device API's data types.
//
// One set serves both OPRoS flavours (docs/opros.md). The 2014 types live in namespace OPRoS: the
// value wrappers here (Bool, Int16, ..., Float64Array, StringArray: a `ReturnType status` and a
// `data`) and the sensor and motion records of OprosDeviceData.h (MobileVelocityData, ...). The
// 2012 types (ObjectLocation, ObjectPosition, ObjectPosture, ...) are also in namespace OPRoS and
// are made global by using-declarations, as 2012 code names them unqualified. Every type has
// save/load members and a typeName. This header also brings the device math helpers
// (OprosMath.h), <cassert>, and std::vector/valarray/string/map usable unqualified. The types are
// values; one object is not shared between threads without a lock.
#ifndef KEEL_OPROS_DEVICE_API_TYPES_H
#define KEEL_OPROS_DEVICE_API_TYPES_H

#include <cassert>
#include <cstdint>
#include <map>
#include <string>
#include <valarray>
#include <vector>

#include "../ReturnType.h"
#include "../archive/opros_archive.h"
#include "OprosMath.h"

// OPRoS #defined these three; keel declares them as types.
typedef char char_t;
typedef float float32_t;
typedef double float64_t;

using std::map;
using std::string;
using std::valarray;
using std::vector;

namespace OPRoS {
namespace detail {

// A value and the status of the call that produced it.
template <typename T>
class StatusValue {
 public:
  StatusValue() = default;
  StatusValue(const T& value) : data(value) {}  // NOLINT(google-explicit-constructor): as OPRoS

  ReturnType status = OPROS_SUCCESS;
  T data{};

  void save(opros::archive::oarchive& ar, const unsigned int) {
    ar << status;
    ar << data;
  }
  void load(opros::archive::iarchive& ar, const unsigned int) {
    ar >> status;
    ar >> data;
  }
};

}  // namespace detail

#define KEEL_OPROS_STATUS_VALUE(Name, Type)       \
  class Name : public detail::StatusValue<Type> { \
   public:                                        \
    using StatusValue::StatusValue;               \
  };                                              \
  inline std::string typeName(Name*) { return #Name; }

KEEL_OPROS_STATUS_VALUE(Bool, bool)
KEEL_OPROS_STATUS_VALUE(Char, char_t)
KEEL_OPROS_STATUS_VALUE(Int8, std::int8_t)
KEEL_OPROS_STATUS_VALUE(UInt8, std::uint8_t)
KEEL_OPROS_STATUS_VALUE(Int16, std::int16_t)
KEEL_OPROS_STATUS_VALUE(UInt16, std::uint16_t)
KEEL_OPROS_STATUS_VALUE(Int32, std::int32_t)
KEEL_OPROS_STATUS_VALUE(UInt32, std::uint32_t)
KEEL_OPROS_STATUS_VALUE(Int64, std::int64_t)
KEEL_OPROS_STATUS_VALUE(UInt64, std::uint64_t)
KEEL_OPROS_STATUS_VALUE(Float32, float32_t)
KEEL_OPROS_STATUS_VALUE(Float64, float64_t)
KEEL_OPROS_STATUS_VALUE(String, std::string)
KEEL_OPROS_STATUS_VALUE(BoolArray, std::vector<bool>)
KEEL_OPROS_STATUS_VALUE(CharArray, std::vector<char_t>)
KEEL_OPROS_STATUS_VALUE(Int8Array, std::vector<std::int8_t>)
KEEL_OPROS_STATUS_VALUE(UInt8Array, std::vector<std::uint8_t>)
KEEL_OPROS_STATUS_VALUE(Int16Array, std::vector<std::int16_t>)
KEEL_OPROS_STATUS_VALUE(UInt16Array, std::vector<std::uint16_t>)
KEEL_OPROS_STATUS_VALUE(Int32Array, std::vector<std::int32_t>)
KEEL_OPROS_STATUS_VALUE(UInt32Array, std::vector<std::uint32_t>)
KEEL_OPROS_STATUS_VALUE(Int64Array, std::vector<std::int64_t>)
KEEL_OPROS_STATUS_VALUE(UInt64Array, std::vector<std::uint64_t>)
KEEL_OPROS_STATUS_VALUE(Float32Array, std::vector<float32_t>)
KEEL_OPROS_STATUS_VALUE(Float64Array, std::vector<float64_t>)
KEEL_OPROS_STATUS_VALUE(StringArray, std::vector<std::string>)

#undef KEEL_OPROS_STATUS_VALUE

}  // namespace OPRoS

#include "OprosDeviceData.h"

#endif  // KEEL_OPROS_DEVICE_API_TYPES_H
