// Construction of TriangleBvh: a binary tree by binned SAH, collapsed into the 4-wide one.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "sensors/triangle_bvh.hpp"

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
constexpr int kMaxDepth = TriangleBvh::kMaxBuildDepth;
constexpr double kBoxPadM = TriangleBvh::kBoxPadM;

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
}  // namespace

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

}  // namespace statebench::sensors
