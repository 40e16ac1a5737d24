// Private to TriangleBvh's walks (triangle_bvh.cpp, triangle_bvh_packet.cpp): the float box
// test's helpers and the exact double-precision triangle test they share.
#pragma once

#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/eigen_types.hpp"
#include "sensors/triangle_bvh.hpp"

namespace statebench::sensors::bvh_kernels {

// At most 3 children pushed per level (4 written).
inline constexpr int kStackSize = 4 * TriangleBvh::kMaxBuildDepth + 8;
inline constexpr double kBoxPadM = TriangleBvh::kBoxPadM;
inline constexpr double kRangeSlackM = 1e-6;  // as the reference kernel's window slack
inline constexpr double kBarycentricSlack = 1e-9;

using V4 = float __attribute__((vector_size(16)));
using V4i = std::int32_t __attribute__((vector_size(16)));

// Bit k set when lane k of a comparison result is true (all ones).
inline unsigned MaskOf(V4i lanes) {
#if defined(__SSE2__)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(lanes)));
#else
  return (lanes[0] & 1u) | (lanes[1] & 2u) | (lanes[2] & 4u) | (lanes[3] & 8u);
#endif
}

// Boxes are culled against the best range so far, padded for float rounding.
inline float LimitOf(double range_m) {
  return static_cast<float>(range_m * (1.0 + 1e-6) + kBoxPadM);
}

inline double Intersect(const Vec3& o, const Vec3& d, const Vec3& v0, const Vec3& e1,
                        const Vec3& e2) {
  const Vec3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (det == 0.0) return -1.0;  // parallel to the plane
  const double inv = 1.0 / det;
  const Vec3 s = o - v0;
  const double u = s.dot(p) * inv;
  if (u < -kBarycentricSlack || u > 1.0 + kBarycentricSlack) return -1.0;
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) * inv;
  if (v < -kBarycentricSlack || u + v > 1.0 + kBarycentricSlack) return -1.0;
  return e2.dot(q) * inv;
}

}  // namespace statebench::sensors::bvh_kernels
