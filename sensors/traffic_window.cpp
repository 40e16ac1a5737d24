#include "sensors/traffic_window.hpp"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace statebench::sensors {
namespace {

// Margin on the swept boxes: covers float rounding of the Bullet tree (coordinates up to a few
// km carry ~1e-4 m of rounding).
constexpr double kSweptMarginM = 0.01;

btVector3 ToBt(const Vec3& v) {
  return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()),
                   static_cast<btScalar>(v.z()));
}

Mat3 BoxRotation(const TrafficBox& box) {
  // Yaw about z, then nose-up pitch (a negative rotation about the box's y axis, which points
  // left).
  return (Eigen::AngleAxisd(box.yaw_rad, Vec3::UnitZ()) *
          Eigen::AngleAxisd(-box.pitch_rad, Vec3::UnitY()))
      .toRotationMatrix();
}

double BoundingRadius(const TrafficBox& b) {
  return 0.5 * std::sqrt(b.length_m * b.length_m + b.width_m * b.width_m + b.height_m * b.height_m);
}

struct Collector : btDbvt::ICollide {
  explicit Collector(std::vector<int>* out) : ids(out) {}
  void Process(const btDbvtNode* leaf) override {
    ids->push_back(static_cast<int>(reinterpret_cast<std::intptr_t>(leaf->data)));
  }
  std::vector<int>* ids;
};

struct Scratch {
  btAlignedObjectArray<const btDbvtNode*> stack;
  std::vector<int> ids;
};

}  // namespace

struct TrafficWindow::Tree {
  btDbvt dbvt;
};

std::optional<RayHit> IntersectTrafficBox(const TrafficBox& box, const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m) {
  const Mat3 r = BoxRotation(box);
  const Vec3 o = r.transpose() * (origin_world - box.centre_world);
  const Vec3 d = r.transpose() * unit_direction_world;
  const Vec3 half(0.5 * box.length_m, 0.5 * box.width_m, 0.5 * box.height_m);
  double t_enter = -std::numeric_limits<double>::infinity();
  double t_exit = std::numeric_limits<double>::infinity();
  int enter_axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (std::abs(o[i]) > half[i]) return std::nullopt;
      continue;
    }
    double t_a = (-half[i] - o[i]) / d[i];
    double t_b = (half[i] - o[i]) / d[i];
    if (t_a > t_b) std::swap(t_a, t_b);
    if (t_a > t_enter) {
      t_enter = t_a;
      enter_axis = i;
    }
    t_exit = std::min(t_exit, t_b);
  }
  if (enter_axis < 0 || t_enter > t_exit || t_enter <= 0.0 || t_enter > max_range_m) {
    return std::nullopt;
  }
  Vec3 n_box = Vec3::Zero();
  n_box[enter_axis] = d[enter_axis] > 0.0 ? -1.0 : 1.0;
  return RayHit{t_enter, r * n_box, SurfaceMaterial::kVehicle};
}

TrafficWindow::TrafficWindow(const TrafficTimeline& traffic, TimeNs t0_ns, TimeNs t1_ns,
                             const Eigen::AlignedBox3d& region)
    : motions_(traffic.MotionsIn(t0_ns, t1_ns)), tree_(std::make_unique<Tree>()) {
  for (std::size_t i = 0; i < motions_.size(); ++i) {
    // The centre moves linearly within a piece, so the box stays inside the bounding spheres
    // swept between the centres at the clipped piece ends.
    Eigen::AlignedBox3d swept;
    for (const TrafficPiece& p : motions_[i].pieces) {
      const TimeNs a = std::max(p.t_begin_ns, t0_ns);
      const TimeNs b = std::min(p.t_end_ns, t1_ns);
      if (a > b) continue;
      for (const TimeNs t : {a, b}) {
        const TrafficBox box = p.At(t);
        const Vec3 pad = Vec3::Constant(BoundingRadius(box) + kSweptMarginM);
        swept.extend(box.centre_world - pad);
        swept.extend(box.centre_world + pad);
      }
    }
    if (swept.isEmpty() || !swept.intersects(region)) continue;
    const btDbvtVolume volume = btDbvtVolume::FromMM(ToBt(swept.min()), ToBt(swept.max()));
    tree_->dbvt.insert(volume, reinterpret_cast<void*>(static_cast<std::intptr_t>(i)));
  }
}

TrafficWindow::~TrafficWindow() = default;

std::optional<RayHit> TrafficWindow::Cast(const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m,
                                          TimeNs t_ns) const {
  if (tree_->dbvt.m_root == nullptr) return std::nullopt;
  thread_local Scratch scratch;
  scratch.ids.clear();
  const btVector3 from = ToBt(origin_world);
  const btVector3 to = ToBt(origin_world + max_range_m * unit_direction_world);
  btVector3 dir = to - from;
  const btScalar lambda_max = dir.length();
  dir /= lambda_max;
  btVector3 inv;
  unsigned int signs[3];
  for (int i = 0; i < 3; ++i) {
    inv[i] = dir[i] == btScalar(0) ? btScalar(BT_LARGE_FLOAT) : btScalar(1) / dir[i];
    signs[i] = inv[i] < 0 ? 1u : 0u;
  }
  Collector collector(&scratch.ids);
  tree_->dbvt.rayTestInternal(tree_->dbvt.m_root, from, to, inv, signs, lambda_max,
                              btVector3(0, 0, 0), btVector3(0, 0, 0), scratch.stack, collector);

  std::optional<RayHit> best;
  double best_range = max_range_m;
  std::sort(scratch.ids.begin(), scratch.ids.end());  // order-independent result, stable ties
  for (const int id : scratch.ids) {
    const TrafficPiece* piece = motions_[static_cast<std::size_t>(id)].PieceAt(t_ns);
    if (piece == nullptr) continue;
    if (auto hit =
            IntersectTrafficBox(piece->At(t_ns), origin_world, unit_direction_world, best_range)) {
      if (!best || hit->range_m < best_range) {
        best_range = hit->range_m;
        best = hit;
      }
    }
  }
  return best;
}

}  // namespace statebench::sensors
