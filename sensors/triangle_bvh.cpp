#include "sensors/triangle_bvh.hpp"

#include <algorithm>
#include <bit>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace statebench::sensors {

// Node of the binary tree the 4-wide one is collapsed from.
struct BvhBinaryNode {
  Eigen::AlignedBox3d box;  // relative to the origin, exact
  std::int32_t first = 0;   // leaf: first triangle; inner: index of the right child
  std::int32_t count = 0;   // leaf: number of triangles (> 0); inner: 0 (left child at index + 1)
};

namespace {

constexpr int kMaxLeafTriangles = 4;
constexpr int kMaxSahLeafTriangles = 8;  // a node this small may stay a leaf when SAH says so
constexpr int kBins = 16;
constexpr int kMaxDepth = 48;    // deeper than this, nodes are split at the middle of their list
constexpr int kStackSize = 4 * kMaxDepth + 8;  // at most 3 children pushed per level, 4 written
constexpr double kBoxPadM = 1e-3;
constexpr double kRangeSlackM = 1e-6;  // as the reference kernel's window slack
constexpr double kBarycentricSlack = 1e-9;

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

// A pushed subtree and where the ray enters its box.
struct Entry {
  std::int32_t ref;  // >= 0 a node, < 0 a leaf
  float t;
};

struct Item {
  Eigen::AlignedBox3d box;  // relative to the origin
  Vec3 centroid;
};

double HalfArea(const Eigen::AlignedBox3d& b) {
  if (b.isEmpty()) return 0.0;
  const Vec3 e = b.sizes();
  return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
}

// Outward rounding of a padded box coordinate to float.
float Below(double x) {
  const double y = x - kBoxPadM;
  float f = static_cast<float>(y);
  if (static_cast<double>(f) > y) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float Above(double x) {
  const double y = x + kBoxPadM;
  float f = static_cast<float>(y);
  if (static_cast<double>(f) < y) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

class Builder {
 public:
  Builder(const std::vector<Item>& items, std::vector<BvhBinaryNode>* nodes, std::vector<int>* order)
      : items_(items), nodes_(*nodes), order_(*order) {}

  // Builds the subtree over order[begin, end) and returns its node's index.
  std::int32_t Build(int begin, int end, int depth) {
    const auto index = static_cast<std::int32_t>(nodes_.size());
    nodes_.emplace_back();
    Eigen::AlignedBox3d box;
    Eigen::AlignedBox3d centroids;
    for (int k = begin; k < end; ++k) {
      box.extend(items_[order_[k]].box);
      centroids.extend(items_[order_[k]].centroid);
    }
    nodes_[index].box = box;
    const int n = end - begin;
    if (n <= kMaxLeafTriangles) return MakeLeaf(index, begin, n);

    int mid = begin + n / 2;  // without a useful split: the middle of the list
    if (depth < kMaxDepth) {
      const Split split = BestSplit(begin, end, centroids);
      if (split.axis >= 0) {
        if (n <= kMaxSahLeafTriangles && split.cost >= static_cast<double>(n) * HalfArea(box)) {
          return MakeLeaf(index, begin, n);
        }
        const double lo = centroids.min()[split.axis];
        const double scale = kBins / (centroids.max()[split.axis] - lo);
        const int* at = std::partition(order_.data() + begin, order_.data() + end, [&](int t) {
          return BinOf(items_[t].centroid[split.axis], lo, scale) < split.bin;
        });
        const int m = static_cast<int>(at - order_.data());
        if (m > begin && m < end) mid = m;
      }
    }
    Build(begin, mid, depth + 1);  // the left child, at index + 1
    const std::int32_t right = Build(mid, end, depth + 1);
    nodes_[index].first = right;
    nodes_[index].count = 0;
    return index;
  }

 private:
  struct Split {
    int axis = -1;
    int bin = 0;  // triangles in bins below go left
    double cost = std::numeric_limits<double>::infinity();
  };

  static int BinOf(double c, double lo, double scale) {
    return std::clamp(static_cast<int>((c - lo) * scale), 0, kBins - 1);
  }

  std::int32_t MakeLeaf(std::int32_t index, int begin, int n) {
    nodes_[index].first = begin;
    nodes_[index].count = n;
    return index;
  }

  // Binned surface-area heuristic over the three axes: cost A_l N_l + A_r N_r.
  Split BestSplit(int begin, int end, const Eigen::AlignedBox3d& centroids) const {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = centroids.min()[axis];
      const double extent = centroids.max()[axis] - lo;
      if (!(extent > 0.0)) continue;
      const double scale = kBins / extent;
      std::array<Eigen::AlignedBox3d, kBins> boxes;
      std::array<int, kBins> counts{};
      for (int k = begin; k < end; ++k) {
        const Item& item = items_[order_[k]];
        const int b = BinOf(item.centroid[axis], lo, scale);
        boxes[b].extend(item.box);
        ++counts[b];
      }
      std::array<double, kBins> left_cost{};
      Eigen::AlignedBox3d left;
      int left_n = 0;
      for (int b = 0; b + 1 < kBins; ++b) {
        left.extend(boxes[b]);
        left_n += counts[b];
        left_cost[b + 1] = HalfArea(left) * left_n;
      }
      Eigen::AlignedBox3d right;
      int right_n = 0;
      for (int b = kBins - 1; b >= 1; --b) {
        right.extend(boxes[b]);
        right_n += counts[b];
        const int left_count = (end - begin) - right_n;
        if (left_count == 0 || right_n == 0) continue;
        const double cost = left_cost[b] + HalfArea(right) * right_n;
        if (cost < best.cost) best = {axis, b, cost};
      }
    }
    return best;
  }

  const std::vector<Item>& items_;
  std::vector<BvhBinaryNode>& nodes_;
  std::vector<int>& order_;
};

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

}  // namespace

double IntersectTriangle(const Vec3& o, const Vec3& d, const Vec3& v0, const Vec3& e1,
                         const Vec3& e2) {
  return Intersect(o, d, v0, e1, e2);
}

TriangleBvh::TriangleBvh(const std::vector<const TriangleMesh*>& meshes, const Vec3& origin)
    : origin_(origin) {
  std::size_t total = 0;
  for (const TriangleMesh* mesh : meshes) total += mesh->triangles.size();
  std::vector<Triangle> all;
  std::vector<Item> items;
  all.reserve(total);
  items.reserve(total);
  for (const TriangleMesh* mesh : meshes) {
    for (std::size_t k = 0; k < mesh->triangles.size(); ++k) {
      const auto& t = mesh->triangles[k];
      const Vec3& v0 = mesh->vertices[t[0]];
      const Vec3& v1 = mesh->vertices[t[1]];
      const Vec3& v2 = mesh->vertices[t[2]];
      all.push_back({v0, v1 - v0, v2 - v0, mesh->materials[k]});
      Item item;
      for (const Vec3* v : {&v0, &v1, &v2}) item.box.extend(*v - origin);
      item.centroid = item.box.center();
      items.push_back(item);
    }
  }
  if (all.empty()) return;
  std::vector<int> order(all.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::vector<BvhBinaryNode> binary;
  binary.reserve(2 * all.size() / kMaxLeafTriangles + 1);
  Builder(items, &binary, &order).Build(0, static_cast<int>(order.size()), 0);
  triangles_.reserve(all.size());
  for (const int k : order) triangles_.push_back(all[k]);
  Collapse(binary);
}

// Each 4-wide node takes the children of a binary node and, while it has fewer than four, opens
// its largest inner child (by surface area) in place.
void TriangleBvh::Collapse(const std::vector<BvhBinaryNode>& binary) {
  // A leaf's reference (~ its index in leaves_).
  const auto leaf_reference = [&](std::int32_t b) -> std::int32_t {
    leaves_.push_back({binary[static_cast<std::size_t>(b)].first,
                       binary[static_cast<std::size_t>(b)].count});
    return ~static_cast<std::int32_t>(leaves_.size() - 1);
  };
  // (4-wide node, slot) to fill with the subtree of binary node b.
  struct Pending {
    std::int32_t node;
    int slot;
    std::int32_t binary;
  };
  std::vector<Pending> pending;
  // The node over binary node b: its children (b itself when b is a leaf, which only the root of
  // a tree of one leaf is).
  const auto make = [&](std::int32_t b) -> std::int32_t {
    std::vector<std::int32_t> children;
    const auto open = [&](std::int32_t inner) {
      children.push_back(inner + 1);
      children.push_back(binary[static_cast<std::size_t>(inner)].first);
    };
    if (binary[static_cast<std::size_t>(b)].count > 0) {
      children.push_back(b);
    } else {
      open(b);
    }
    while (children.size() < 4) {
      int widest = -1;
      double area = -1.0;
      for (std::size_t k = 0; k < children.size(); ++k) {
        const BvhBinaryNode& c = binary[static_cast<std::size_t>(children[k])];
        if (c.count == 0 && HalfArea(c.box) > area) {
          area = HalfArea(c.box);
          widest = static_cast<int>(k);
        }
      }
      if (widest < 0) break;
      const std::int32_t inner = children[static_cast<std::size_t>(widest)];
      children.erase(children.begin() + widest);
      open(inner);
    }
    Node node{};
    node.count = static_cast<std::int32_t>(children.size());
    const auto index = static_cast<std::int32_t>(nodes_.size());
    for (int k = 0; k < 4; ++k) {
      for (int i = 0; i < 3; ++i) {
        // Unused slots: an empty box no ray enters (lo > hi).
        node.lo[i][k] = 1.0f;
        node.hi[i][k] = -1.0f;
      }
      node.child[k] = 0;
    }
    for (int k = 0; k < node.count; ++k) {
      const BvhBinaryNode& c = binary[static_cast<std::size_t>(children[static_cast<std::size_t>(k)])];
      for (int i = 0; i < 3; ++i) {
        node.lo[i][k] = Below(c.box.min()[i]);
        node.hi[i][k] = Above(c.box.max()[i]);
      }
      const std::int32_t b = children[static_cast<std::size_t>(k)];
      if (c.count > 0) {
        node.child[k] = leaf_reference(b);
      } else {
        pending.push_back({index, k, b});  // an inner node: made below
      }
    }
    nodes_.push_back(node);
    return index;
  };
  make(0);
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    const std::int32_t child = make(p.binary);
    nodes_[static_cast<std::size_t>(p.node)].child[p.slot] = child;
  }
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
        Entry met[4];  // by decreasing entry
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
