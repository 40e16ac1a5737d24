// TriangleBvh::CastPacket: up to kPacketSize (25) rays walk the tree together. Each node is
// loaded and decided once for the packet: its boxes are tested child by child against a group
// of rays at a time (the rays side by side in SIMD lanes: 4 with SSE, 8 with AVX2 where the CPU
// has it; per ray and box the single-ray test's float operations, so the same verdicts and
// entries on either path), a child is walked with the rays that met it, nearest first by the
// smallest entry among them, and the others are pushed with each ray's entry. Leaves intersect
// each of their rays exactly, in double, as Cast does. A ray is dropped from a subtree only when
// it misses the subtree's box or enters it beyond the ray's own best hit, so each ray gets
// Cast's range.
//
// The AVX2 path is the same template compiled inside a function with the "avx2" target (no FMA:
// no product is fused with a sum, so the doubles of the exact test round as on the SSE path),
// chosen once at run time (__builtin_cpu_supports); other compilers and CPUs take the SSE path.
#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <iterator>

#include "sensors/triangle_bvh.hpp"
#include "sensors/triangle_bvh_kernels.hpp"

#if defined(__clang__) && defined(__x86_64__)
#define STATEBENCH_BVH_AVX2 1
// The 8-lane helpers pass AVX vectors by value, which -Wpsabi flags for functions built without
// AVX; they are all always_inline into the "avx2" function, so no vector crosses a call.
#pragma clang diagnostic ignored "-Wpsabi"
#endif

namespace statebench::sensors {
namespace {

using bvh_kernels::Intersect;
using bvh_kernels::kRangeSlackM;
using bvh_kernels::kStackSize;
using bvh_kernels::LimitOf;

constexpr int kLanes = TriangleBvh::kPacketSize;
static_assert(kLanes >= 1 && kLanes <= 32);

// W rays side by side: their floats, and the all-ones / zero lanes of a comparison.
template <int W>
struct Lanes {
  static_assert(W == 4 || W == 8);
  using F = float __attribute__((vector_size(4 * W)));
  using I = std::int32_t __attribute__((vector_size(4 * W)));
  static constexpr int kGroups = (kLanes + W - 1) / W;
  static constexpr int kPadded = W * kGroups;
  static constexpr unsigned kGroupMask = (1u << W) - 1u;

  [[gnu::always_inline]] static F Load(const float* p) {
    F v;
    std::memcpy(&v, p, sizeof(v));
    return v;
  }
  [[gnu::always_inline]] static void Store(float* p, const F& v) {
    std::memcpy(p, &v, sizeof(v));
  }
  [[gnu::always_inline]] static F Splat(float x) {
    F v;
    for (int i = 0; i < W; ++i) v[i] = x;
    return v;
  }
  // Bit k set when lane k is all ones.
  [[gnu::always_inline]] static unsigned Mask(const I& lanes) {
#if defined(STATEBENCH_BVH_AVX2)
    I bits;
    for (int i = 0; i < W; ++i) bits[i] = 1 << i;
    return static_cast<unsigned>(__builtin_reduce_or(lanes & bits));
#else
    static_assert(W == 4);
    return bvh_kernels::MaskOf(lanes);
#endif
  }
  // Lane k all ones where bit k of bits is set.
  [[gnu::always_inline]] static I LanesOf(unsigned bits) {
    I v;
    for (int i = 0; i < W; ++i) v[i] = ((bits >> i) & 1u) != 0 ? -1 : 0;
    return v;
  }
  // The W rays of group g among `rays`.
  [[gnu::always_inline]] static unsigned GroupBits(unsigned rays, int g) {
    return (rays >> (W * g)) & kGroupMask;
  }
};

constexpr int kDoubleGroups = (kLanes + 3) / 4;
constexpr int kDoublePadded = 4 * kDoubleGroups;

#if defined(STATEBENCH_BVH_AVX2)
// Four rays' exact triangle test side by side (the AVX2 walk's leaves): bvh_kernels::Intersect's
// operations on each lane, in its order (Eigen's cross and dot products on Vec3), so each lane's
// range has the scalar test's bits.
struct DoubleLanes {
  using D = double __attribute__((vector_size(32)));
  using I = std::int64_t __attribute__((vector_size(32)));

  [[gnu::always_inline]] static D Load(const double* p) {
    D v;
    std::memcpy(&v, p, sizeof(v));
    return v;
  }
  [[gnu::always_inline]] static D Splat(double x) { return D{x, x, x, x}; }
  [[gnu::always_inline]] static D Dot(const D& ax, const D& ay, const D& az, const D& bx,
                                      const D& by, const D& bz) {
    return (ax * bx + ay * by) + az * bz;
  }
  // Bit k: lane k of rays [first, first + 4) hits the triangle at range[k] (> 0, < best).
  [[gnu::always_inline]] static unsigned Intersect(const double (&o)[3][kDoublePadded],
                                                   const double (&d)[3][kDoublePadded],
                                                   int first, const Vec3& v0, const Vec3& e1,
                                                   const Vec3& e2, const double* best,
                                                   double* range) {
    using bvh_kernels::kBarycentricSlack;
    const D dx = Load(d[0] + first), dy = Load(d[1] + first), dz = Load(d[2] + first);
    const D e1x = Splat(e1.x()), e1y = Splat(e1.y()), e1z = Splat(e1.z());
    const D e2x = Splat(e2.x()), e2y = Splat(e2.y()), e2z = Splat(e2.z());
    // p = d x e2
    const D px = dy * e2z - dz * e2y;
    const D py = dz * e2x - dx * e2z;
    const D pz = dx * e2y - dy * e2x;
    const D det = Dot(e1x, e1y, e1z, px, py, pz);
    const D inv = Splat(1.0) / det;
    const D sx = Load(o[0] + first) - Splat(v0.x());
    const D sy = Load(o[1] + first) - Splat(v0.y());
    const D sz = Load(o[2] + first) - Splat(v0.z());
    const D u = Dot(sx, sy, sz, px, py, pz) * inv;
    // q = s x e1
    const D qx = sy * e1z - sz * e1y;
    const D qy = sz * e1x - sx * e1z;
    const D qz = sx * e1y - sy * e1x;
    const D v = Dot(dx, dy, dz, qx, qy, qz) * inv;
    const D r = Dot(e2x, e2y, e2z, qx, qy, qz) * inv;
    const D lo = Splat(-kBarycentricSlack);
    const D hi = Splat(1.0 + kBarycentricSlack);
    const I miss = (det == Splat(0.0)) | (u < lo) | (u > hi) | (v < lo) | (u + v > hi);
    const I ok = ~miss & (r > Splat(0.0)) & (r < Load(best));
    std::memcpy(range, &r, sizeof(r));
    const I bit{1, 2, 4, 8};
    return static_cast<unsigned>(__builtin_reduce_or(ok & bit));
  }
};
#endif

// A pushed subtree, the rays that met its box and where each entered it (t read for those rays
// only).
template <int W>
struct PacketEntry {
  std::int32_t ref;  // >= 0 a node, < 0 a leaf
  unsigned rays;     // bit l: ray l
  alignas(4 * W) float t[Lanes<W>::kPadded];
};

// A child a node's test met: its slot in the node, the rays that met it and the smallest entry.
struct MetChild {
  int slot;
  unsigned rays;
  float nearest;
};

}  // namespace

template <int W>
[[gnu::always_inline]] inline void TriangleBvh::WalkPacket(const Vec3* origins,
                                                           const Vec3* directions, int count,
                                                           double max_range_m,
                                                           std::optional<RayHit>* hits) const {
  using L = Lanes<W>;
  using F = typename L::F;
  using I = typename L::I;
  constexpr int kGroups = L::kGroups;
  constexpr int kPadded = L::kPadded;
  for (int l = 0; l < count; ++l) hits[l].reset();
  if (nodes_.empty()) return;
  // The rays in the float box test's terms, lane l of group l / W: origin relative to the BVH's
  // origin, 1 / d, and on each axis whether the box's hi face is met first (d < 0). Lanes past
  // count are never active.
  alignas(4 * W) float origin[3][kPadded] = {};
  alignas(4 * W) float inverse[3][kPadded];
  alignas(4 * W) float limit[kPadded];
  I hi_first[3][kGroups];
  alignas(32) std::array<double, kDoublePadded> best;
  std::array<int, kLanes> best_triangle;
  // The AVX2 walk's exact test: origins and directions (world frame, double) by axis.
  alignas(32) double ray_o[3][kDoublePadded];
  alignas(32) double ray_d[3][kDoublePadded];
  alignas(32) double range[4];
  if constexpr (W == 8) {
    for (int i = 0; i < 3; ++i) {
      std::fill(std::begin(ray_o[i]), std::end(ray_o[i]), 0.0);
      std::fill(std::begin(ray_d[i]), std::end(ray_d[i]), 1.0);
      for (int l = 0; l < count; ++l) {
        ray_o[i][l] = origins[l][i];
        ray_d[i][l] = directions[l][i];
      }
    }
  }
  std::fill(best.begin(), best.end(), 0.0);
  for (int i = 0; i < 3; ++i) std::fill(std::begin(inverse[i]), std::end(inverse[i]), 1.0f);
  std::fill(std::begin(limit), std::end(limit), -1.0f);
  for (int l = 0; l < count; ++l) {
    const Vec3 rel = origins[l] - origin_;
    for (int i = 0; i < 3; ++i) {
      const auto di = static_cast<float>(directions[l][i]);
      origin[i][l] = static_cast<float>(rel[i]);
      inverse[i][l] = std::abs(di) > 1e-30f ? 1.0f / di : std::copysign(1e30f, di);
    }
    best[static_cast<std::size_t>(l)] = max_range_m + kRangeSlackM;
    best_triangle[static_cast<std::size_t>(l)] = -1;
    limit[l] = LimitOf(best[static_cast<std::size_t>(l)]);
  }
  for (int i = 0; i < 3; ++i) {
    for (int g = 0; g < kGroups; ++g) {
      hi_first[i][g] = L::Load(inverse[i] + W * g) < L::Splat(0.0f);
    }
  }

  std::array<PacketEntry<W>, kStackSize> stack;
  int top = 0;
  std::int32_t ref = 0;
  unsigned active = count == 32 ? ~0u : (1u << count) - 1u;
  alignas(4 * W) float entry[4][kPadded];  // per child, each ray's entry (read where it met)
  for (;;) {
    if (ref >= 0) {
      const Node& n = nodes_[static_cast<std::size_t>(ref)];
      // Per child, the rays that met its box and their entries. Children past n.count have
      // empty boxes no ray meets.
      unsigned met[4] = {0u, 0u, 0u, 0u};
      for (int k = 0; k < n.count; ++k) {
        F lo[3];
        F hi[3];
        for (int i = 0; i < 3; ++i) {
          lo[i] = L::Splat(n.lo[i][k]);
          hi[i] = L::Splat(n.hi[i][k]);
        }
        for (int g = 0; g < kGroups; ++g) {
          const unsigned bits = L::GroupBits(active, g);
          if (bits == 0) continue;
          F t_near = L::Splat(0.0f);
          F t_far = L::Load(limit + W * g);
          for (int i = 0; i < 3; ++i) {
            const I h = hi_first[i][g];
            const F near_face = h ? hi[i] : lo[i];
            const F far_face = h ? lo[i] : hi[i];
            const F o = L::Load(origin[i] + W * g);
            const F inv = L::Load(inverse[i] + W * g);
            const F a = (near_face - o) * inv;
            const F b = (far_face - o) * inv;
            t_near = t_near > a ? t_near : a;
            t_far = t_far < b ? t_far : b;
          }
          met[k] |= (L::Mask(t_near <= t_far) & bits) << (W * g);
          L::Store(entry[k] + W * g, t_near);
        }
      }
      // The children met, by decreasing smallest entry among their rays.
      MetChild children[4];
      int count_met = 0;
      for (int k = 0; k < n.count; ++k) {
        if (met[k] == 0) continue;
        F smallest = L::Splat(3.0e38f);
        for (int g = 0; g < kGroups; ++g) {
          const unsigned bits = L::GroupBits(met[k], g);
          if (bits == 0) continue;
          const F e = L::Load(entry[k] + W * g);
          smallest = (L::LanesOf(bits) & (e < smallest)) ? e : smallest;
        }
        float nearest = smallest[0];
        for (int i = 1; i < W; ++i) nearest = std::min(nearest, smallest[i]);
        const MetChild c{k, met[k], nearest};
        int at = count_met++;
        while (at > 0 && children[at - 1].nearest < c.nearest) {
          children[at] = children[at - 1];
          --at;
        }
        children[at] = c;
      }
      if (count_met > 0) {
        // All but the nearest pushed, each with its rays' entries.
        for (int m = 0; m + 1 < count_met; ++m) {
          PacketEntry<W>& e = stack[static_cast<std::size_t>(top++)];
          e.ref = n.child[children[m].slot];
          e.rays = children[m].rays;
          std::memcpy(e.t, entry[children[m].slot], sizeof(e.t));
        }
        ref = n.child[children[count_met - 1].slot];
        active = children[count_met - 1].rays;
        continue;
      }
    } else {
      const Leaf& leaf = leaves_[static_cast<std::size_t>(~ref)];
      for (int k = leaf.first; k < leaf.first + leaf.count; ++k) {
        const Triangle& t = triangles_[static_cast<std::size_t>(k)];
#if defined(STATEBENCH_BVH_AVX2)
        if constexpr (W == 8) {
          // Four rays at a time in double lanes, every step of Intersect in its order.
          for (int g = 0; g < kDoubleGroups; ++g) {
            const unsigned bits = (active >> (4 * g)) & 0xFu;
            if (bits == 0) continue;
            unsigned hit = DoubleLanes::Intersect(ray_o, ray_d, 4 * g, t.v0, t.e1, t.e2,
                                                  best.data() + 4 * g, range) &
                           bits;
            for (; hit != 0; hit &= hit - 1) {
              const auto l = static_cast<std::size_t>(4 * g + std::countr_zero(hit));
              best[l] = range[l - 4 * static_cast<std::size_t>(g)];
              best_triangle[l] = k;
              limit[l] = LimitOf(best[l]);
            }
          }
          continue;
        }
#endif
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
      const PacketEntry<W>& e = stack[static_cast<std::size_t>(--top)];
      unsigned still = 0;
      for (int g = 0; g < kGroups; ++g) {
        const unsigned bits = L::GroupBits(e.rays, g);
        if (bits == 0) continue;
        still |= (L::Mask(L::Load(e.t + W * g) <= L::Load(limit + W * g)) & bits) << (W * g);
      }
      if (still != 0) {
        ref = e.ref;
        active = still;
        break;
      }
    }
  }
}

void TriangleBvh::CastPacket(const Vec3* origins, const Vec3* directions, int count,
                             double max_range_m, std::optional<RayHit>* hits,
                             PacketKernel kernel) const {
  assert(count >= 1 && count <= kLanes);
#if defined(STATEBENCH_BVH_AVX2)
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  if (avx2 && kernel == PacketKernel::kBest) {
    return CastPacketAvx2(origins, directions, count, max_range_m, hits);
  }
#else
  (void)kernel;
#endif
  WalkPacket<4>(origins, directions, count, max_range_m, hits);
}

#if defined(STATEBENCH_BVH_AVX2)
__attribute__((target("avx2"))) void TriangleBvh::CastPacketAvx2(
    const Vec3* origins, const Vec3* directions, int count, double max_range_m,
    std::optional<RayHit>* hits) const {
  WalkPacket<8>(origins, directions, count, max_range_m, hits);
}
#else
void TriangleBvh::CastPacketAvx2(const Vec3* origins, const Vec3* directions, int count,
                                 double max_range_m, std::optional<RayHit>* hits) const {
  WalkPacket<4>(origins, directions, count, max_range_m, hits);
}
#endif

}  // namespace statebench::sensors
