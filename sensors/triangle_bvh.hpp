// A flat bounding-volume hierarchy over every triangle of the lidar world, the kernel of
// LidarWorld::CastStatic. Built once as a binary tree (binned surface-area heuristic, up to 4
// triangles a leaf), then collapsed into a 4-wide tree whose nodes hold their four children's
// boxes side by side (structure of arrays, one 128-byte node), so one step tests four boxes at
// once in SIMD (GCC/Clang vector extensions: SSE on x86-64, NEON on ARM). Walked nearest child
// first with a small stack of (node, entry range), culling in single precision and ranging in
// double:
//   - boxes are float, relative to `origin` (as Bullet's), rounded outwards and padded by 1 mm,
//     so a ray that meets a triangle always meets every box above it (the float ray is off by
//     micrometres at most);
//   - every triangle a leaf proposes is intersected exactly, in double (Moller-Trumbore on the
//     world-frame vertices), so ranges are those of the Bullet-walk reference kernel
//     (LidarWorld::CastStaticBullet) whatever the float boxes.
// CastPacket walks up to kPacketSize rays together (triangle_bvh_packet.cpp): each node is
// fetched and decided once for the packet, each ray keeps its own box tests, culling and best
// hit, so each gets Cast's range. A lidar channel over adjacent columns (nearly one origin, 0.18
// degrees apart) meets nearly the same nodes. The rays sit side by side in SIMD lanes (box tests
// 4 or 8 rays at a time, and on the AVX2 path the exact tests 4 at a time), chosen at run time:
// about 1.6x Cast's rays per CPU second on the dense town with SSE, 2.5x with AVX2.
// Read-only after construction: Cast and CastPacket are thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/ray_hit.hpp"
#include "sensors/world_mesh.hpp"

namespace statebench::sensors {

// Exact ray / triangle intersection in double (Moller-Trumbore) with the triangle given as v0 and
// its edges e1 = v1 - v0, e2 = v2 - v0. Returns the range along the unit direction d, or a negative
// value when missed. Barycentric coordinates may be off by 1e-9 so that a ray through a shared
// edge hits one of the two triangles.
double IntersectTriangle(const Vec3& o, const Vec3& d, const Vec3& v0, const Vec3& e1,
                         const Vec3& e2);

struct BvhBinaryNode;  // the binary tree while building (triangle_bvh_build.cpp)

class TriangleBvh {
 public:
  static constexpr int kMaxBuildDepth = 48;  // deeper, nodes are split at their list's middle
  static constexpr double kBoxPadM = 1e-3;   // node boxes padded by this much (and rounded out)

  TriangleBvh(const std::vector<const TriangleMesh*>& meshes, const Vec3& origin);

  // Closest triangle along o + r d, 0 < r <= max_range_m (d a unit vector, world frame).
  std::optional<RayHit> Cast(const Vec3& o, const Vec3& d, double max_range_m) const;

  // The same for `count` (1 to kPacketSize) rays walked together, hits[k] for ray k: the ranges
  // Cast gives (the triangle too, unless two lie at exactly the same range). Cheaper per ray
  // when the rays are close (e.g. one channel of adjacent lidar columns: they meet nearly the
  // same nodes).
  // kernel: kBest takes the AVX2 walk where the CPU has it (8 rays per SIMD group), kSse the
  // 4-ray walk every x86-64 CPU runs; both give the same hits bit for bit.
  static constexpr int kPacketSize = 25;
  enum class PacketKernel { kBest, kSse };
  void CastPacket(const Vec3* origins, const Vec3* directions, int count, double max_range_m,
                  std::optional<RayHit>* hits, PacketKernel kernel = PacketKernel::kBest) const;

  std::size_t node_count() const { return nodes_.size(); }
  std::size_t triangle_count() const { return triangles_.size(); }

 private:
  // Four children's boxes (relative to origin_); child[k] >= 0: a node, < 0: leaf ~child[k]
  // (an index into leaves_); children [count, 4) are unused.
  struct alignas(16) Node {
    float lo[3][4];
    float hi[3][4];
    std::int32_t child[4];
    std::int32_t count;
    std::int32_t pad[3];
  };
  static_assert(sizeof(Node) == 128);

  struct Leaf {
    std::int32_t first;  // into triangles_
    std::int32_t count;
  };

  // Exact triangle: v0 and the edges v1 - v0, v2 - v0 (world frame, double).
  struct Triangle {
    Vec3 v0;
    Vec3 e1;
    Vec3 e2;
    SurfaceMaterial material;
  };

  void Collapse(const std::vector<BvhBinaryNode>& binary);
  // CastPacket's walk with W rays per SIMD group (triangle_bvh_packet.cpp), and its AVX2 build.
  template <int W>
  void WalkPacket(const Vec3* origins, const Vec3* directions, int count, double max_range_m,
                  std::optional<RayHit>* hits) const;
  void CastPacketAvx2(const Vec3* origins, const Vec3* directions, int count,
                      double max_range_m, std::optional<RayHit>* hits) const;
  // The hit on triangle `triangle` (-1: none) at range_m along d, its normal facing the ray.
  std::optional<RayHit> HitOf(int triangle, double range_m, const Vec3& d) const;

  std::vector<Node> nodes_;  // the root first
  std::vector<Leaf> leaves_;
  std::vector<Triangle> triangles_;  // in leaf order
  Vec3 origin_;
};

}  // namespace statebench::sensors
