// TriangleBvh::CastPacket: up to kPacketSize (25) rays walk the tree together. Each node is
// loaded and decided once for the packet: every active ray tests the node's four boxes (the
// single-ray test, same floats), a child is walked with the rays that met it, nearest first by
// the smallest entry among them, and the others are pushed with each ray's entry. Leaves
// intersect each of their rays exactly, as Cast does. A ray is dropped from a subtree only when
// it misses the subtree's box or enters it beyond the ray's own best hit, so each ray gets
// Cast's range.
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>

#include "sensors/triangle_bvh.hpp"
#include "sensors/triangle_bvh_kernels.hpp"

namespace statebench::sensors {
namespace {

using bvh_kernels::Intersect;
using bvh_kernels::kRangeSlackM;
using bvh_kernels::kStackSize;
using bvh_kernels::LimitOf;
using bvh_kernels::MaskOf;
using bvh_kernels::V4;

constexpr int kLanes = TriangleBvh::kPacketSize;
static_assert(kLanes >= 1 && kLanes <= 32);

// One ray in the float box test's terms.
struct PacketRay {
  V4 origin[3];      // relative to the BVH's origin, all lanes equal
  V4 inverse[3];     // 1 / d
  int near_face[3];  // 0: the box's lo face is met first on this axis, 1: its hi face
};

// A pushed subtree, the rays that met its box and where each entered it (t set for those rays
// only).
struct PacketEntry {
  std::int32_t ref;  // >= 0 a node, < 0 a leaf
  unsigned rays;     // bit l: ray l
  float t[kLanes];
};

// A child a node's test met: its slot in the node, the rays that met it and the smallest entry.
struct MetChild {
  int slot;
  unsigned rays;
  float nearest;
};

}  // namespace

void TriangleBvh::CastPacket(const Vec3* origins, const Vec3* directions, int count,
                             double max_range_m, std::optional<RayHit>* hits) const {
  assert(count >= 1 && count <= kLanes);
  for (int l = 0; l < count; ++l) hits[l].reset();
  if (nodes_.empty()) return;
  std::array<PacketRay, kLanes> rays;
  std::array<double, kLanes> best;
  std::array<int, kLanes> best_triangle;
  std::array<float, kLanes> limit;
  for (int l = 0; l < count; ++l) {
    const Vec3 rel = origins[l] - origin_;
    for (int i = 0; i < 3; ++i) {
      const auto oi = static_cast<float>(rel[i]);
      const auto di = static_cast<float>(directions[l][i]);
      const float inv = std::abs(di) > 1e-30f ? 1.0f / di : std::copysign(1e30f, di);
      rays[l].origin[i] = V4{oi, oi, oi, oi};
      rays[l].inverse[i] = V4{inv, inv, inv, inv};
      rays[l].near_face[i] = inv < 0.0f ? 1 : 0;
    }
    best[l] = max_range_m + kRangeSlackM;
    best_triangle[l] = -1;
    limit[l] = LimitOf(best[l]);
  }

  std::array<PacketEntry, kStackSize> stack;
  int top = 0;
  std::int32_t ref = 0;
  unsigned active = count == 32 ? ~0u : (1u << count) - 1u;
  for (;;) {
    if (ref >= 0) {
      const Node& n = nodes_[static_cast<std::size_t>(ref)];
      const float* faces[2][3] = {{n.lo[0], n.lo[1], n.lo[2]}, {n.hi[0], n.hi[1], n.hi[2]}};
      // Per ray: the children met (bits) and the entries.
      unsigned met[kLanes];  // read for the active rays only
      V4 entry[kLanes];
      unsigned any = 0;
      for (unsigned lanes = active; lanes != 0; lanes &= lanes - 1) {
        const int l = std::countr_zero(lanes);
        const PacketRay& ray = rays[static_cast<std::size_t>(l)];
        const float lim = limit[static_cast<std::size_t>(l)];
        V4 t_near = V4{0.0f, 0.0f, 0.0f, 0.0f};
        V4 t_far = V4{lim, lim, lim, lim};
        for (int i = 0; i < 3; ++i) {
          V4 near_face;
          V4 far_face;
          std::memcpy(&near_face, faces[ray.near_face[i]][i], sizeof(near_face));
          std::memcpy(&far_face, faces[1 - ray.near_face[i]][i], sizeof(far_face));
          const V4 a = (near_face - ray.origin[i]) * ray.inverse[i];
          const V4 b = (far_face - ray.origin[i]) * ray.inverse[i];
          t_near = t_near > a ? t_near : a;
          t_far = t_far < b ? t_far : b;
        }
        met[l] = MaskOf(t_near <= t_far);
        entry[l] = t_near;
        any |= met[l];
      }
      if (any != 0) {
        // The children met, by decreasing smallest entry among their rays.
        MetChild children[4];
        int count_met = 0;
        for (; any != 0; any &= any - 1) {
          const int k = std::countr_zero(any);
          MetChild c{k, 0u, 3.0e38f};
          for (unsigned lanes = active; lanes != 0; lanes &= lanes - 1) {
            const int l = std::countr_zero(lanes);
            if ((met[l] >> k) & 1u) {
              c.rays |= 1u << l;
              c.nearest = std::min(c.nearest, entry[l][k]);
            }
          }
          int at = count_met++;
          while (at > 0 && children[at - 1].nearest < c.nearest) {
            children[at] = children[at - 1];
            --at;
          }
          children[at] = c;
        }
        // All but the nearest pushed, each with its rays' entries.
        for (int m = 0; m + 1 < count_met; ++m) {
          PacketEntry& e = stack[static_cast<std::size_t>(top++)];
          e.ref = n.child[children[m].slot];
          e.rays = children[m].rays;
          for (unsigned lanes = e.rays; lanes != 0; lanes &= lanes - 1) {
            const int l = std::countr_zero(lanes);
            e.t[l] = entry[l][children[m].slot];
          }
        }
        ref = n.child[children[count_met - 1].slot];
        active = children[count_met - 1].rays;
        continue;
      }
    } else {
      const Leaf& leaf = leaves_[static_cast<std::size_t>(~ref)];
      for (int k = leaf.first; k < leaf.first + leaf.count; ++k) {
        const Triangle& t = triangles_[static_cast<std::size_t>(k)];
        for (unsigned lanes = active; lanes != 0; lanes &= lanes - 1) {
          const auto l = static_cast<std::size_t>(std::countr_zero(lanes));
          const double r = Intersect(origins[l], directions[l], t.v0, t.e1, t.e2);
          if (r > 0.0 && r < best[l]) {
            best[l] = r;
            best_triangle[l] = k;
            limit[l] = LimitOf(r);
          }
        }
      }
    }
    // The next entry that some ray may still need.
    for (;;) {
      if (top == 0) {
        for (int l = 0; l < count; ++l) {
          hits[l] = HitOf(best_triangle[static_cast<std::size_t>(l)],
                          best[static_cast<std::size_t>(l)], directions[l]);
        }
        return;
      }
      const PacketEntry& e = stack[static_cast<std::size_t>(--top)];
      unsigned still = 0;
      for (unsigned lanes = e.rays; lanes != 0; lanes &= lanes - 1) {
        const int l = std::countr_zero(lanes);
        if (e.t[l] <= limit[static_cast<std::size_t>(l)]) still |= 1u << l;
      }
      if (still != 0) {
        ref = e.ref;
        active = still;
        break;
      }
    }
  }
}

}  // namespace statebench::sensors
