#include "sensors/traffic_window.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sensors {
namespace {

// Margin on the swept boxes (rounding; the balls are only used to cull).
constexpr double kSweptMarginM = 0.01;

double BoundingRadius(const TrafficBox& b) {
  return 0.5 * std::sqrt(b.length_m * b.length_m + b.width_m * b.width_m + b.height_m * b.height_m);
}

}  // namespace

TrafficWindow::TrafficWindow(const TrafficTimeline& traffic, TimeNs t0_ns, TimeNs t1_ns,
                             const Eigen::AlignedBox3d& region)
    : motions_(traffic.MotionsIn(t0_ns, t1_ns)) {
  for (std::size_t i = 0; i < motions_.size(); ++i) {
    // The centre moves linearly within a piece and the sizes change linearly (the bounding
    // radius is convex in them), so the box stays inside the bounding balls at the clipped piece
    // ends and inside the box around them.
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
    balls_.push_back({i, swept.center(), 0.5 * swept.sizes().norm()});
  }
}

void TrafficWindow::PoseFor(const RayFan& fan_world, const Vec3& origin_world, double max_range_m,
                            TimeNs t_ns, std::vector<PosedTrafficBox>* out) const {
  out->clear();
  for (const SweptBall& ball : balls_) {
    if (!fan_world.MayMeetBall(origin_world, max_range_m, ball.centre_world, ball.radius_m)) {
      continue;
    }
    const TrafficPiece* piece = motions_[ball.motion].PieceAt(t_ns);
    if (piece == nullptr) continue;
    const PosedTrafficBox box = PoseTrafficBox(piece->At(t_ns));
    if (fan_world.MayMeetBall(origin_world, max_range_m, box.centre_world, box.radius_m)) {
      out->push_back(box);
    }
  }
}

std::optional<RayHit> TrafficWindow::Cast(const std::vector<PosedTrafficBox>& posed,
                                          const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m) {
  std::optional<RayHit> best;
  double best_range = max_range_m;
  for (const PosedTrafficBox& box : posed) {
    if (!MayMeetBox(box, origin_world, unit_direction_world, best_range)) continue;
    if (auto hit = IntersectTrafficBox(box, origin_world, unit_direction_world, best_range)) {
      if (!best || hit->range_m < best_range) {
        best_range = hit->range_m;
        best = hit;
      }
    }
  }
  return best;
}

std::optional<RayHit> TrafficWindow::Cast(const Vec3& origin_world,
                                          const Vec3& unit_direction_world, double max_range_m,
                                          TimeNs t_ns) const {
  std::vector<PosedTrafficBox> posed;
  PoseFor(FanOf({&unit_direction_world, 1}), origin_world, max_range_m, t_ns, &posed);
  return Cast(posed, origin_world, unit_direction_world, max_range_m);
}

}  // namespace statebench::sensors
