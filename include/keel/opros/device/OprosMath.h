// OprosMath.h — keel's own, from-scratch OPRoS-compatible version of the device API's math
// helpers (degree/radian conversion, angle differences, distances), which 2012 components use
// unqualified after including ApiTypes.h. Header-only, stateless, thread-safe.
#ifndef KEEL_OPROS_DEVICE_OPROS_MATH_H
#define KEEL_OPROS_DEVICE_OPROS_MATH_H

#include <cmath>
#include <cstdlib>
#include <limits>
#include <utility>
#include <valarray>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

// A quiet NaN, as OPRoS's `NaN`.
inline const double NaN = std::numeric_limits<double>::quiet_NaN();

inline double RAD2DEG(double x) { return x * (180.0 / M_PI); }
inline double DEG2RAD(double x) { return x * (M_PI / 180.0); }

template <typename T>
inline T min_val(T v1, T v2) {
  return (v1 < v2) ? v1 : v2;
}
template <typename T>
inline T max_val(T v1, T v2) {
  return (v1 > v2) ? v1 : v2;
}
// x clamped to [l, u].
template <typename T>
inline T bound(T x, T l, T u) {
  return x <= l ? l : (x >= u ? u : x);
}
template <typename T>
inline void Swap(T& v1, T& v2) {
  std::swap(v1, v2);
}

// result = src's (x, y) rotated by rad.
inline void Rotate(double result[3], const double src[3], double rad) {
  const double c = std::cos(rad);
  const double s = std::sin(rad);
  const double x = src[0] * c - src[1] * s;
  const double y = src[0] * s + src[1] * c;
  result[0] = x;
  result[1] = y;
}

// a rounded half away from zero.
inline int INTEGER(const double a) { return (0 < a) ? static_cast<int>(a + 0.5) : static_cast<int>(a - 0.5); }
inline double Sign(const double v) { return (0 < v) ? +1. : -1.; }

// ang1 - ang2 in (-180, 180) degrees.
inline int DeltaDeg(int ang1, int ang2) {
  int da = (ang1 - ang2) % 360;
  if (da >= 180) {
    da -= 360;
  } else if (da <= -180) {
    da += 360;
  }
  return da;
}
inline double DeltaDeg(double ang1, double ang2) {
  double da = std::fmod(ang1 - ang2, 360.0);
  if (da >= 180) {
    da -= 360;
  } else if (da <= -180) {
    da += 360;
  }
  return da;
}
// ang1 - ang2 in (-pi, pi) radians.
inline double DeltaRad(double ang1, double ang2) {
  double da = std::fmod(ang1 - ang2, 2 * M_PI);
  if (da >= M_PI) {
    da -= 2 * M_PI;
  } else if (da <= -M_PI) {
    da += 2 * M_PI;
  }
  return da;
}

inline double Length(double x, double y) { return std::sqrt(x * x + y * y); }
inline double Distance(double x1, double y1, double x2, double y2) { return Length(x2 - x1, y2 - y1); }
inline int Distance(int x1, int y1, int x2, int y2) {
  return INTEGER(Length(static_cast<double>(x2 - x1), static_cast<double>(y2 - y1)));
}

// Not NaN (OPRoS's Linux version answered false for everything).
inline bool IsNum(double num) { return !std::isnan(num); }
inline int CountNum(const std::valarray<double>& v) {
  int count = 0;
  for (double x : v) count += IsNum(x) ? 1 : 0;
  return count;
}
// v with its NaNs replaced by 0 (v itself too, as OPRoS).
inline std::valarray<double> FilterNaN(std::valarray<double>& v) {
  for (double& x : v) {
    if (!IsNum(x)) x = 0.;
  }
  return v;
}

#endif  // KEEL_OPROS_DEVICE_OPROS_MATH_H
