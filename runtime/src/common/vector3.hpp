/// \file vector3.hpp
/// Internal (not installed): 3-vector arithmetic on raw `double[3]` for the
/// surface and octree code, which keeps coordinates in flat arrays.
#ifndef TENSORMASS_VECTOR3_HPP
#define TENSORMASS_VECTOR3_HPP

#include <cmath>

namespace tensormass::detail {

inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void sub(const double* a, const double* b, double* out) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}
inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline double norm(const double* a) { return std::sqrt(dot(a, a)); }

}  // namespace tensormass::detail

#endif
