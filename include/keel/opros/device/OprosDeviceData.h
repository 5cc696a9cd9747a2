// OprosDeviceData.h — keel's own, from-scratch OPRoS-compatible device records (part of
// ApiTypes.h, which includes this file; include ApiTypes.h).
//
// 2014 records carry a `ReturnType status` first: MobilePositionData, MobileVelocityData,
// MobileAccelerationData (x, y, theta), ObjectPositionData, ObjectVelocityData,
// ObjectAccelerationData (x, y, z, roll, pitch, yaw), AccelerationSensorData, GyroSensorData,
// GeoMagneticSensorData, ImuData, CameraData, GpsData. 2012 records have none: ObjectPosition,
// ObjectRotation, ObjectPosture, ObjectLocation, JoystickData, VisionRecognitionResult,
// ColorRange, CartesianCoordinate, ForceTorqueSensorData, CanData; those (and GpsData, which
// both flavours have) are also global names. Each record lists its fields once, in fields(),
// which its save/load (and the 2012 element-wise operators) follow. Values, not shared.
#ifndef KEEL_OPROS_DEVICE_OPROS_DEVICE_DATA_H
#define KEEL_OPROS_DEVICE_OPROS_DEVICE_DATA_H

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "../ReturnType.h"
#include "../archive/opros_archive.h"
#include "ApiTypes.h"  // float64_t; when included first, ApiTypes.h includes this file back
#include "OprosMath.h"

namespace OPRoS {
namespace detail {

template <typename T>
void save_fields(opros::archive::oarchive& ar, T& record) {
  std::apply([&](auto... field) { ((ar << record.*field), ...); }, T::fields());
}

template <typename T>
void load_fields(opros::archive::iarchive& ar, T& record) {
  std::apply([&](auto... field) { ((ar >> record.*field), ...); }, T::fields());
}

// left with op applied to each field and the same field of right.
template <typename T, typename Op>
T elementwise(T left, const T& right, Op op) {
  std::apply([&](auto... field) { ((left.*field = op(left.*field, right.*field)), ...); }, T::fields());
  return left;
}

// save/load members that follow fields().
#define KEEL_OPROS_RECORD_SERIALIZATION                                                           \
  void save(opros::archive::oarchive& ar, const unsigned int) { detail::save_fields(ar, *this); } \
  void load(opros::archive::iarchive& ar, const unsigned int) { detail::load_fields(ar, *this); }

// A planar pose or motion with a status (2014).
class PlanarRecord {
 public:
  PlanarRecord() = default;
  PlanarRecord(float64_t xValue, float64_t yValue, float64_t thetaValue) : x(xValue), y(yValue), theta(thetaValue) {}

  ReturnType status = OPROS_SUCCESS;
  float64_t x = 0;
  float64_t y = 0;
  float64_t theta = 0;

  static constexpr auto fields() {
    return std::make_tuple(&PlanarRecord::status, &PlanarRecord::x, &PlanarRecord::y, &PlanarRecord::theta);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};

// A spatial pose or motion with a status (2014).
class SpatialRecord {
 public:
  SpatialRecord() = default;
  SpatialRecord(float64_t xValue, float64_t yValue, float64_t zValue, float64_t rollValue, float64_t pitchValue,
                float64_t yawValue)
      : x(xValue), y(yValue), z(zValue), roll(rollValue), pitch(pitchValue), yaw(yawValue) {}

  ReturnType status = OPROS_SUCCESS;
  float64_t x = 0;
  float64_t y = 0;
  float64_t z = 0;
  float64_t roll = 0;
  float64_t pitch = 0;
  float64_t yaw = 0;

  static constexpr auto fields() {
    return std::make_tuple(&SpatialRecord::status, &SpatialRecord::x, &SpatialRecord::y, &SpatialRecord::z,
                           &SpatialRecord::roll, &SpatialRecord::pitch, &SpatialRecord::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};

}  // namespace detail

#define KEEL_OPROS_RECORD(Name, Base) \
  class Name : public detail::Base {  \
   public:                            \
    using Base::Base;                 \
  };                                  \
  inline std::string typeName(Name*) { return #Name; }

KEEL_OPROS_RECORD(MobilePositionData, PlanarRecord)
KEEL_OPROS_RECORD(MobileVelocityData, PlanarRecord)
KEEL_OPROS_RECORD(MobileAccelerationData, PlanarRecord)
KEEL_OPROS_RECORD(ObjectPositionData, SpatialRecord)
KEEL_OPROS_RECORD(ObjectVelocityData, SpatialRecord)
KEEL_OPROS_RECORD(ObjectAccelerationData, SpatialRecord)

#undef KEEL_OPROS_RECORD

class AccelerationSensorData {
 public:
  ReturnType status = OPROS_SUCCESS;
  float64_t xAcceleration = 0;
  float64_t yAcceleration = 0;
  float64_t zAcceleration = 0;

  static constexpr auto fields() {
    using R = AccelerationSensorData;
    return std::make_tuple(&R::status, &R::xAcceleration, &R::yAcceleration, &R::zAcceleration);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(AccelerationSensorData*) { return "AccelerationSensorData"; }

class GyroSensorData {
 public:
  ReturnType status = OPROS_SUCCESS;
  float64_t xAngle = 0;
  float64_t yAngle = 0;
  float64_t zAngle = 0;
  float64_t xAngleRate = 0;
  float64_t yAngleRate = 0;
  float64_t zAngleRate = 0;

  static constexpr auto fields() {
    using R = GyroSensorData;
    return std::make_tuple(&R::status, &R::xAngle, &R::yAngle, &R::zAngle, &R::xAngleRate, &R::yAngleRate,
                           &R::zAngleRate);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(GyroSensorData*) { return "GyroSensorData"; }

class GeoMagneticSensorData {
 public:
  ReturnType status = OPROS_SUCCESS;
  float64_t xGauss = 0;
  float64_t yGauss = 0;
  float64_t zGauss = 0;
  float64_t xGaussRate = 0;
  float64_t yGaussRate = 0;
  float64_t zGaussRate = 0;
  float64_t xAlpha = 0;
  float64_t yAlpha = 0;
  float64_t zAlpha = 0;

  static constexpr auto fields() {
    using R = GeoMagneticSensorData;
    return std::make_tuple(&R::status, &R::xGauss, &R::yGauss, &R::zGauss, &R::xGaussRate, &R::yGaussRate,
                           &R::zGaussRate, &R::xAlpha, &R::yAlpha, &R::zAlpha);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(GeoMagneticSensorData*) { return "GeoMagneticSensorData"; }

class ImuData {
 public:
  ReturnType status = OPROS_SUCCESS;
  float64_t pRate = 0;
  float64_t qRate = 0;
  float64_t rRate = 0;
  float64_t xAcceleration = 0;
  float64_t yAcceleration = 0;
  float64_t zAcceleration = 0;
  float64_t roll = 0;
  float64_t pitch = 0;
  float64_t yaw = 0;

  static constexpr auto fields() {
    using R = ImuData;
    return std::make_tuple(&R::status, &R::pRate, &R::qRate, &R::rRate, &R::xAcceleration, &R::yAcceleration,
                           &R::zAcceleration, &R::roll, &R::pitch, &R::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ImuData*) { return "ImuData"; }

class CameraData {
 public:
  ReturnType status = OPROS_SUCCESS;
  std::int32_t format = 0;
  std::int32_t width = 0;
  std::int32_t height = 0;
  std::vector<std::uint8_t> data;

  static constexpr auto fields() {
    using R = CameraData;
    return std::make_tuple(&R::status, &R::format, &R::width, &R::height, &R::data);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(CameraData*) { return "CameraData"; }

// Both flavours; 2012's had no status.
class GpsData {
 public:
  GpsData() = default;
  GpsData(float64_t latitudeValue, float64_t longitudeValue, const std::string& timeValue, float64_t velocityValue)
      : latitude(latitudeValue), longitude(longitudeValue), time(timeValue), velocity(velocityValue) {}

  ReturnType status = OPROS_SUCCESS;
  float64_t latitude = 0;
  float64_t longitude = 0;
  std::string time;
  float64_t velocity = 0;

  static constexpr auto fields() {
    using R = GpsData;
    return std::make_tuple(&R::status, &R::latitude, &R::longitude, &R::time, &R::velocity);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(GpsData*) { return "GpsData"; }

// ---- 2012 records (no status) ----

class ObjectPosition {
 public:
  ObjectPosition() = default;
  ObjectPosition(double xValue, double yValue, double zValue, double rollValue, double pitchValue, double yawValue)
      : x(xValue), y(yValue), z(zValue), roll(rollValue), pitch(pitchValue), yaw(yawValue) {}

  double x = 0;
  double y = 0;
  double z = 0;
  double roll = 0;
  double pitch = 0;
  double yaw = 0;

  // Element-wise; unlike OPRoS's, they leave the left operand unchanged.
  ObjectPosition operator+(const ObjectPosition& o) const { return detail::elementwise(*this, o, std::plus<>()); }
  ObjectPosition operator-(const ObjectPosition& o) const { return detail::elementwise(*this, o, std::minus<>()); }
  ObjectPosition operator*(const ObjectPosition& o) const { return detail::elementwise(*this, o, std::multiplies<>()); }
  ObjectPosition operator/(const ObjectPosition& o) const { return detail::elementwise(*this, o, std::divides<>()); }

  static constexpr auto fields() {
    using R = ObjectPosition;
    return std::make_tuple(&R::x, &R::y, &R::z, &R::roll, &R::pitch, &R::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ObjectPosition*) { return "ObjectPosition"; }

class ObjectRotation {
 public:
  ObjectRotation() = default;
  ObjectRotation(double rollValue, double pitchValue, double yawValue)
      : roll(rollValue), pitch(pitchValue), yaw(yawValue) {}

  double roll = 0;
  double pitch = 0;
  double yaw = 0;

  ObjectRotation operator+(const ObjectRotation& o) const { return detail::elementwise(*this, o, std::plus<>()); }
  ObjectRotation operator-(const ObjectRotation& o) const { return detail::elementwise(*this, o, std::minus<>()); }
  ObjectRotation operator*(const ObjectRotation& o) const { return detail::elementwise(*this, o, std::multiplies<>()); }
  ObjectRotation operator/(const ObjectRotation& o) const { return detail::elementwise(*this, o, std::divides<>()); }

  static constexpr auto fields() {
    return std::make_tuple(&ObjectRotation::roll, &ObjectRotation::pitch, &ObjectRotation::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ObjectRotation*) { return "ObjectRotation"; }

class ObjectPosture {
 public:
  double pRate = 0;
  double qRate = 0;
  double rRate = 0;
  double xAcceleration = 0;
  double yAcceleration = 0;
  double zAcceleration = 0;
  double roll = 0;
  double pitch = 0;
  double yaw = 0;

  ObjectPosture operator+(const ObjectPosture& o) const { return detail::elementwise(*this, o, std::plus<>()); }
  ObjectPosture operator-(const ObjectPosture& o) const { return detail::elementwise(*this, o, std::minus<>()); }
  ObjectPosture operator*(const ObjectPosture& o) const { return detail::elementwise(*this, o, std::multiplies<>()); }
  ObjectPosture operator/(const ObjectPosture& o) const { return detail::elementwise(*this, o, std::divides<>()); }

  static constexpr auto fields() {
    using R = ObjectPosture;
    return std::make_tuple(&R::pRate, &R::qRate, &R::rRate, &R::xAcceleration, &R::yAcceleration, &R::zAcceleration,
                           &R::roll, &R::pitch, &R::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ObjectPosture*) { return "ObjectPosture"; }

// A planar pose: position (x, y) and heading theta in radians.
class ObjectLocation {
 public:
  double x = 0;
  double y = 0;
  double theta = 0;

  ObjectLocation() = default;
  // The point at distance len in direction th, heading th.
  ObjectLocation(double len, double th) : x(len * std::cos(th)), y(len * std::sin(th)), theta(th) {}
  ObjectLocation(double xValue, double yValue, double th) : x(xValue), y(yValue), theta(th) {}

  ObjectLocation& operator+=(const ObjectLocation& p) { return *this = detail::elementwise(*this, p, std::plus<>()); }
  ObjectLocation& operator-=(const ObjectLocation& p) { return *this = detail::elementwise(*this, p, std::minus<>()); }
  ObjectLocation& operator*=(const ObjectLocation& p) {
    return *this = detail::elementwise(*this, p, std::multiplies<>());
  }
  ObjectLocation& operator/=(const ObjectLocation& p) {
    return *this = detail::elementwise(*this, p, std::divides<>());
  }
  ObjectLocation& operator*=(double d) {
    x *= d;
    y *= d;
    theta *= d;
    return *this;
  }

  // Rotates the position about the origin by rad and turns the heading by rad.
  ObjectLocation& Rotate(double rad) {
    const double c = std::cos(rad);
    const double s = std::sin(rad);
    const double rotatedX = x * c - y * s;
    y = x * s + y * c;
    x = rotatedX;
    theta += rad;
    return *this;
  }
  ObjectLocation& Translate(double dx, double dy) {
    x += dx;
    y += dy;
    return *this;
  }
  // Into the frame p is expressed in: rotate by p.theta, then translate by p's position.
  ObjectLocation& Transform(const ObjectLocation& p) {
    Rotate(p.theta);
    return Translate(p.x, p.y);
  }

  double Atan() const { return std::atan2(y, x); }
  double Length() const { return std::sqrt(x * x + y * y); }
  double Distance(const ObjectLocation& p) const { return std::hypot(p.x - x, p.y - y); }

  static constexpr auto fields() {
    return std::make_tuple(&ObjectLocation::x, &ObjectLocation::y, &ObjectLocation::theta);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ObjectLocation*) { return "ObjectLocation"; }

// v1 - v2, with the heading difference wrapped into (-pi, pi).
inline ObjectLocation diff(const ObjectLocation& v1, const ObjectLocation& v2) {
  return ObjectLocation(v1.x - v2.x, v1.y - v2.y, DeltaRad(v1.theta, v2.theta));
}

class JoystickData {
 public:
  double x = 0;
  double y = 0;
  double z = 0;
  std::vector<bool> button;

  static constexpr auto fields() {
    return std::make_tuple(&JoystickData::x, &JoystickData::y, &JoystickData::z, &JoystickData::button);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(JoystickData*) { return "JoystickData"; }

class VisionRecognitionResult {
 public:
  std::string name;
  int point1X = 0;
  int point1Y = 0;
  int point2X = 0;
  int point2Y = 0;
  int point3X = 0;
  int point3Y = 0;
  int point4X = 0;
  int point4Y = 0;

  static constexpr auto fields() {
    using R = VisionRecognitionResult;
    return std::make_tuple(&R::name, &R::point1X, &R::point1Y, &R::point2X, &R::point2Y, &R::point3X, &R::point3Y,
                           &R::point4X, &R::point4Y);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(VisionRecognitionResult*) { return "VisionRecognitionResult"; }

class ColorRange {
 public:
  std::string name;
  unsigned char min1 = 0;
  unsigned char max1 = 0;
  unsigned char min2 = 0;
  unsigned char max2 = 0;
  unsigned char min3 = 0;
  unsigned char max3 = 0;

  static constexpr auto fields() {
    using R = ColorRange;
    return std::make_tuple(&R::name, &R::min1, &R::max1, &R::min2, &R::max2, &R::min3, &R::max3);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ColorRange*) { return "ColorRange"; }

class CartesianCoordinate {
 public:
  CartesianCoordinate() = default;
  CartesianCoordinate(double xValue, double yValue, double zValue, double rollValue, double pitchValue, double yawValue)
      : x(xValue), y(yValue), z(zValue), roll(rollValue), pitch(pitchValue), yaw(yawValue) {}

  double x = 0;
  double y = 0;
  double z = 0;
  double roll = 0;
  double pitch = 0;
  double yaw = 0;

  CartesianCoordinate operator+(const CartesianCoordinate& o) const {
    return detail::elementwise(*this, o, std::plus<>());
  }
  CartesianCoordinate operator-(const CartesianCoordinate& o) const {
    return detail::elementwise(*this, o, std::minus<>());
  }

  static constexpr auto fields() {
    using R = CartesianCoordinate;
    return std::make_tuple(&R::x, &R::y, &R::z, &R::roll, &R::pitch, &R::yaw);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(CartesianCoordinate*) { return "CartesianCoordinate"; }

class ForceTorqueSensorData {
 public:
  ForceTorqueSensorData() = default;
  ForceTorqueSensorData(double fxValue, double fyValue, double fzValue, double txValue, double tyValue, double tzValue)
      : fx(fxValue), fy(fyValue), fz(fzValue), tx(txValue), ty(tyValue), tz(tzValue) {}

  double fx = 0;
  double fy = 0;
  double fz = 0;
  double tx = 0;
  double ty = 0;
  double tz = 0;

  ForceTorqueSensorData operator+(const ForceTorqueSensorData& o) const {
    return detail::elementwise(*this, o, std::plus<>());
  }
  ForceTorqueSensorData operator-(const ForceTorqueSensorData& o) const {
    return detail::elementwise(*this, o, std::minus<>());
  }

  static constexpr auto fields() {
    using R = ForceTorqueSensorData;
    return std::make_tuple(&R::fx, &R::fy, &R::fz, &R::tx, &R::ty, &R::tz);
  }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(ForceTorqueSensorData*) { return "ForceTorqueSensorData"; }

class CanData {
 public:
  CanData() = default;
  CanData(long idValue, const std::vector<unsigned char>& bytes) : id(idValue), data(bytes) {}

  long id = 0;
  std::vector<unsigned char> data;

  static constexpr auto fields() { return std::make_tuple(&CanData::id, &CanData::data); }
  KEEL_OPROS_RECORD_SERIALIZATION
};
inline std::string typeName(CanData*) { return "CanData"; }

#undef KEEL_OPROS_RECORD_SERIALIZATION

}  // namespace OPRoS

// The 2012 flavour's global names.
using OPRoS::CanData;
using OPRoS::CartesianCoordinate;
using OPRoS::ColorRange;
using OPRoS::ForceTorqueSensorData;
using OPRoS::GpsData;
using OPRoS::JoystickData;
using OPRoS::ObjectLocation;
using OPRoS::ObjectPosition;
using OPRoS::ObjectPosture;
using OPRoS::ObjectRotation;
using OPRoS::VisionRecognitionResult;

#endif  // KEEL_OPROS_DEVICE_OPROS_DEVICE_DATA_H
