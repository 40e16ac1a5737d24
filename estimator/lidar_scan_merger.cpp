#include "estimator/lidar_scan_merger.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <memory>

#include "core/error.hpp"

namespace statebench::est {

LidarScanMerger::LidarScanMerger(std::vector<LidarMount> mounts,
                                 const LidarScanMergerOptions& options)
    : mounts_(std::move(mounts)),
      options_(options),
      newest_per_lidar_ns_(mounts_.size(), std::numeric_limits<TimeNs>::min()) {
  if (mounts_.empty()) throw InputError("lidar scan merger: no lidar");
  if (options_.period_ns <= 0) throw InputError("lidar scan merger: period must be positive");
  if (options_.max_wait_ns < 0) throw InputError("lidar scan merger: max_wait must be >= 0");
  for (std::size_t i = 0; i < mounts_.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (mounts_[i].id == mounts_[j].id) {
        throw InputError("lidar scan merger: lidar '" + mounts_[i].id + "' given twice");
      }
    }
    diagnostics_.scans_per_lidar[mounts_[i].id] = 0;
    diagnostics_.missing_per_lidar[mounts_[i].id] = 0;
  }
}

int LidarScanMerger::MountIndex(const std::string& id) const {
  for (std::size_t i = 0; i < mounts_.size(); ++i) {
    if (mounts_[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

std::vector<LidarScan> LidarScanMerger::Add(const LidarScan& scan) {
  ++diagnostics_.scans_in;
  std::vector<LidarScan> out;
  const int index = MountIndex(scan.header.sensor_id);
  if (index < 0) {
    ++diagnostics_.unknown;
    return out;
  }
  const TimeNs stamp = scan.header.stamp_ns;
  const TimeNs half = options_.period_ns / 2;
  if (emitted_any_ && stamp < last_emitted_anchor_ns_ + half) {
    ++diagnostics_.late;
    return out;
  }
  auto it = std::find_if(pending_.begin(), pending_.end(),
                         [&](const Period& p) { return std::llabs(stamp - p.anchor_ns) < half; });
  if (it == pending_.end()) {
    Period period;
    period.anchor_ns = stamp;
    period.scans.resize(mounts_.size());
    period.present.assign(mounts_.size(), 0);
    it =
        pending_.insert(std::upper_bound(pending_.begin(), pending_.end(), stamp,
                                         [](TimeNs t, const Period& p) { return t < p.anchor_ns; }),
                        std::move(period));
  }
  if (it->present[index]) {
    ++diagnostics_.duplicates;
  } else {
    it->scans[index] = scan;
    it->present[index] = 1;
    ++it->count;
  }
  newest_stamp_ns_ = std::max(newest_stamp_ns_, stamp);
  newest_per_lidar_ns_[index] = std::max(newest_per_lidar_ns_[index], stamp);
  EmitReady(newest_stamp_ns_, false, &out);
  return out;
}

std::vector<LidarScan> LidarScanMerger::Flush() {
  std::vector<LidarScan> out;
  EmitReady(std::numeric_limits<TimeNs>::max(), true, &out);
  return out;
}

void LidarScanMerger::EmitReady(TimeNs newest_stamp_ns, bool flush, std::vector<LidarScan>* out) {
  while (!pending_.empty()) {
    const Period& oldest = pending_.front();
    const bool complete = oldest.count == mounts_.size();
    const bool timed_out = newest_stamp_ns - oldest.anchor_ns > options_.max_wait_ns;
    bool missing_moved_on = true;  // every missing lidar has sent a scan of a later period
    for (std::size_t i = 0; i < mounts_.size(); ++i) {
      if (!oldest.present[i] &&
          newest_per_lidar_ns_[i] < oldest.anchor_ns + options_.period_ns / 2) {
        missing_moved_on = false;
      }
    }
    if (!complete && !timed_out && !missing_moved_on && !flush) break;
    out->push_back(Merge(oldest));
    emitted_any_ = true;
    last_emitted_anchor_ns_ = oldest.anchor_ns;
    pending_.erase(pending_.begin());
  }
}

LidarScan LidarScanMerger::Merge(const Period& period) {
  LidarScan merged;
  merged.header.sensor_id = options_.merged_id;
  merged.header.stamp_ns = std::numeric_limits<TimeNs>::max();
  std::size_t total = 0;
  for (std::size_t i = 0; i < mounts_.size(); ++i) {
    if (!period.present[i]) {
      ++diagnostics_.missing_per_lidar[mounts_[i].id];
      continue;
    }
    const LidarScan& s = period.scans[i];
    merged.header.stamp_ns = std::min(merged.header.stamp_ns, s.header.stamp_ns);
    merged.header.arrival_ns = std::max(merged.header.arrival_ns, s.header.arrival_ns);
    if (s.points) total += s.points->size();
    ++diagnostics_.scans_per_lidar[mounts_[i].id];
  }
  auto points = std::make_shared<std::vector<LidarPoint>>();
  points->reserve(total);
  for (std::size_t i = 0; i < mounts_.size(); ++i) {
    if (!period.present[i] || !period.scans[i].points) continue;
    const LidarScan& s = period.scans[i];
    const SE3& T = mounts_[i].T_ref_lidar;
    const Mat3 R = T.RotationMatrix();
    const Vec3& t = T.translation();
    // Offset of this lidar's stamp from the merged stamp (>= 0), in seconds.
    const double dt_s = ToSeconds(s.header.stamp_ns - merged.header.stamp_ns);
    for (const LidarPoint& lp : *s.points) {
      const Vec3 p_ref = R * Vec3(lp.x, lp.y, lp.z) + t;
      LidarPoint q = lp;
      q.x = static_cast<float>(p_ref.x());
      q.y = static_cast<float>(p_ref.y());
      q.z = static_cast<float>(p_ref.z());
      q.t = static_cast<float>(static_cast<double>(lp.t) + dt_s);
      points->push_back(q);
    }
  }
  merged.points = std::move(points);
  ++diagnostics_.merged;
  if (period.count < mounts_.size()) ++diagnostics_.incomplete;
  return merged;
}

}  // namespace statebench::est
