#include "sensors/triangle_bvh.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include "sensors/triangle_bvh_kernels.hpp"

namespace statebench::sensors {
namespace {

using bvh_kernels::Intersect;
using bvh_kernels::kRangeSlackM;
using bvh_kernels::kStackSize;
using bvh_kernels::LimitOf;
using bvh_kernels::MaskOf;
using bvh_kernels::V4;

// A pushed subtree and where the ray enters its box.
struct Entry {
  std::int32_t ref;  // >= 0 a node, < 0 a leaf
  float t;
};

}  // namespace

double IntersectTriangle(const Vec3& o, const Vec3& d, const Vec3& v0, const Vec3& e1,
                         const Vec3& e2) {
  return Intersect(o, d, v0, e1, e2);
}

std::optional<RayHit> TriangleBvh::Cast(const Vec3& o, const Vec3& d, double max_range_m) const {
  if (nodes_.empty()) return std::nullopt;
  const Vec3 rel = o - origin_;
  V4 origin[3];
  V4 inverse[3];
  bool negative[3];  // the ray enters a box through its hi face on this axis
  for (int i = 0; i < 3; ++i) {
    const auto oi = static_cast<float>(rel[i]);
    const auto di = static_cast<float>(d[i]);
    const float inv = std::abs(di) > 1e-30f ? 1.0f / di : std::copysign(1e30f, di);
    origin[i] = V4{oi, oi, oi, oi};
    inverse[i] = V4{inv, inv, inv, inv};
    negative[i] = inv < 0.0f;
  }
  double best = max_range_m + kRangeSlackM;
  int best_triangle = -1;
  float limit = LimitOf(best);

  // Walked nearest child first: of the children a node's test meets, the nearest is walked at
  // once and the others pushed, farthest first; popped entries beyond the best hit are dropped.
  std::array<Entry, kStackSize> stack;
  int top = 0;
  std::int32_t ref = 0;  // the node (>= 0) or leaf (< 0) being walked
  for (;;) {
    if (ref >= 0) {
      const Node& n = nodes_[static_cast<std::size_t>(ref)];
      V4 t_near = V4{0.0f, 0.0f, 0.0f, 0.0f};
      V4 t_far = V4{limit, limit, limit, limit};
      for (int i = 0; i < 3; ++i) {
        V4 near_face;
        V4 far_face;
        std::memcpy(&near_face, negative[i] ? n.hi[i] : n.lo[i], sizeof(near_face));
        std::memcpy(&far_face, negative[i] ? n.lo[i] : n.hi[i], sizeof(far_face));
        const V4 a = (near_face - origin[i]) * inverse[i];
        const V4 b = (far_face - origin[i]) * inverse[i];
        t_near = t_near > a ? t_near : a;
        t_far = t_far < b ? t_far : b;
      }
      // Unused slots hold empty boxes (lo > hi), which no ray meets.
      unsigned mask = MaskOf(t_near <= t_far);
      if (mask != 0) {
        if ((mask & (mask - 1)) == 0) {
          ref = n.child[std::countr_zero(mask)];
          continue;
        }
        Entry met[4] = {};  // by decreasing entry
        int count = 0;
        for (; mask != 0; mask &= mask - 1) {
          const int k = std::countr_zero(mask);
          const Entry c{n.child[k], t_near[k]};
          int at = count++;
          while (at > 0 && met[at - 1].t < c.t) {
            met[at] = met[at - 1];
            --at;
          }
          met[at] = c;
        }
        // Fixed-size copy (the unused tail is overwritten later): no call for a variable length.
        for (int k = 0; k < 4; ++k) stack[static_cast<std::size_t>(top + k)] = met[k];
        top += count - 1;
        ref = met[count - 1].ref;
        continue;
      }
    } else {
      const Leaf& leaf = leaves_[static_cast<std::size_t>(~ref)];
      for (int k = leaf.first; k < leaf.first + leaf.count; ++k) {
        const Triangle& t = triangles_[static_cast<std::size_t>(k)];
        const double r = Intersect(o, d, t.v0, t.e1, t.e2);
        if (r > 0.0 && r < best) {
          best = r;
          best_triangle = k;
          limit = LimitOf(best);
        }
      }
    }
    // The next entry that may still hold a closer hit.
    for (;;) {
      if (top == 0) return HitOf(best_triangle, best, d);
      const Entry& e = stack[static_cast<std::size_t>(--top)];
      if (e.t <= limit) {
        ref = e.ref;
        break;
      }
    }
  }
}

std::optional<RayHit> TriangleBvh::HitOf(int triangle, double range_m, const Vec3& d) const {
  if (triangle < 0) return std::nullopt;
  const Triangle& t = triangles_[static_cast<std::size_t>(triangle)];
  Vec3 normal = t.e1.cross(t.e2).normalized();
  if (normal.dot(d) > 0.0) normal = -normal;
  return RayHit{range_m, normal, t.material};
}

}  // namespace statebench::sensors
