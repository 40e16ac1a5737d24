#include "sensors/traffic_timeline.hpp"

#include <algorithm>
#include <map>

#include "core/error.hpp"
#include "core/so3.hpp"

namespace statebench::sensors {
namespace {

void AddPiece(std::map<std::string, TrafficMotion>* motions, const TrafficPiece& piece) {
  TrafficMotion& m = (*motions)[piece.a.id];
  m.id = piece.a.id;
  m.pieces.push_back(piece);
}

TrafficPiece Hold(const TrafficBox& box, TimeNs t_box, TimeNs begin, TimeNs end) {
  return {begin, end, t_box, t_box, box, box};
}

// Pieces of the step between frames f0 and f1 (boxes sorted by id), merged by id.
void StepPieces(const TrafficFrame& f0, const TrafficFrame& f1,
                std::map<std::string, TrafficMotion>* motions) {
  const TimeNs mid = f0.t_ns + (f1.t_ns - f0.t_ns) / 2;
  auto i = f0.boxes.begin();
  auto j = f1.boxes.begin();
  while (i != f0.boxes.end() || j != f1.boxes.end()) {
    if (j == f1.boxes.end() || (i != f0.boxes.end() && i->id < j->id)) {
      AddPiece(motions, Hold(*i, f0.t_ns, f0.t_ns, mid));
      ++i;
    } else if (i == f0.boxes.end() || j->id < i->id) {
      AddPiece(motions, Hold(*j, f1.t_ns, mid, f1.t_ns));
      ++j;
    } else {
      AddPiece(motions, {f0.t_ns, f1.t_ns, f0.t_ns, f1.t_ns, *i, *j});
      ++i;
      ++j;
    }
  }
}

}  // namespace

TrafficBox TrafficPiece::At(TimeNs t_ns) const {
  if (tb_ns == ta_ns) return a;
  const double alpha =
      std::clamp(static_cast<double>(t_ns - ta_ns) / static_cast<double>(tb_ns - ta_ns), 0.0, 1.0);
  TrafficBox box = a;
  box.centre_world = a.centre_world + alpha * (b.centre_world - a.centre_world);
  box.yaw_rad = so3::WrapAngle(a.yaw_rad + alpha * so3::WrapAngle(b.yaw_rad - a.yaw_rad));
  box.pitch_rad = a.pitch_rad + alpha * (b.pitch_rad - a.pitch_rad);
  box.length_m = a.length_m + alpha * (b.length_m - a.length_m);
  box.width_m = a.width_m + alpha * (b.width_m - a.width_m);
  box.height_m = a.height_m + alpha * (b.height_m - a.height_m);
  return box;
}

const TrafficPiece* TrafficMotion::PieceAt(TimeNs t_ns) const {
  for (const TrafficPiece& p : pieces) {
    if (p.t_begin_ns <= t_ns && t_ns < p.t_end_ns) return &p;
  }
  return nullptr;
}

TrafficTimeline::TrafficTimeline(std::vector<TrafficFrame> frames) : frames_(std::move(frames)) {
  for (std::size_t k = 0; k < frames_.size(); ++k) {
    TrafficFrame& f = frames_[k];
    if (k > 0 && f.t_ns <= frames_[k - 1].t_ns) {
      throw InputError("traffic frame " + std::to_string(k) + ": time " + std::to_string(f.t_ns) +
                       " ns does not increase");
    }
    std::sort(f.boxes.begin(), f.boxes.end(),
              [](const TrafficBox& a, const TrafficBox& b) { return a.id < b.id; });
    for (std::size_t i = 1; i < f.boxes.size(); ++i) {
      if (f.boxes[i].id == f.boxes[i - 1].id) {
        throw InputError("traffic frame " + std::to_string(k) + ": vehicle id '" + f.boxes[i].id +
                         "' appears twice");
      }
    }
  }
}

std::vector<TrafficMotion> TrafficTimeline::MotionsIn(TimeNs t0_ns, TimeNs t1_ns) const {
  std::map<std::string, TrafficMotion> motions;
  if (frames_.empty()) return {};
  constexpr TimeNs kMin = std::numeric_limits<TimeNs>::min();
  constexpr TimeNs kMax = std::numeric_limits<TimeNs>::max();
  if (t0_ns < frames_.front().t_ns) {
    for (const TrafficBox& b : frames_.front().boxes) {
      AddPiece(&motions, Hold(b, frames_.front().t_ns, kMin, frames_.front().t_ns));
    }
  }
  // Steps [t_k, t_k+1) that intersect [t0, t1].
  const auto by_time = [](const TrafficFrame& f, TimeNs t) { return f.t_ns < t; };
  auto first = std::lower_bound(frames_.begin(), frames_.end(), t0_ns, by_time);
  if (first != frames_.begin()) --first;
  for (auto k = first; k + 1 != frames_.end() && k->t_ns <= t1_ns; ++k) {
    StepPieces(*k, *(k + 1), &motions);
  }
  if (t1_ns >= frames_.back().t_ns) {
    for (const TrafficBox& b : frames_.back().boxes) {
      AddPiece(&motions, Hold(b, frames_.back().t_ns, frames_.back().t_ns, kMax));
    }
  }
  std::vector<TrafficMotion> out;
  out.reserve(motions.size());
  for (auto& [id, m] : motions) {
    std::sort(m.pieces.begin(), m.pieces.end(), [](const TrafficPiece& a, const TrafficPiece& b) {
      return a.t_begin_ns < b.t_begin_ns;
    });
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<TrafficBox> TrafficTimeline::BoxesAt(TimeNs t_ns) const {
  std::vector<TrafficBox> out;
  for (const TrafficMotion& m : MotionsIn(t_ns, t_ns)) {
    if (const TrafficPiece* p = m.PieceAt(t_ns)) out.push_back(p->At(t_ns));
  }
  return out;
}

}  // namespace statebench::sensors
