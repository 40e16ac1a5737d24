// Merges the scans of several lidars rigidly mounted on one vehicle into one scan per scan
// period, in a reference frame chosen by the caller (e.g. the first lidar's frame or the IMU).
//
// Frames and times: lidar i reports point p_i(t) in its own frame at time stamp_i + t. With the
// static extrinsic T_ref_lidar_i, the same point in the reference frame at the same time is
// p_ref(t) = T_ref_lidar_i p_i(t) (exact for a rigid mount). The merged scan's stamp is the
// earliest stamp of the group, and each point's offset is re-expressed from it:
// t_merged = t + (stamp_i - stamp_merged). Deskewing the merged scan with the motion of the
// reference frame is then as exact as deskewing each lidar with its own motion.
//
// Grouping: a scan joins the pending period whose anchor (the stamp of the period's first scan
// received) is within half a period of its stamp, else it opens a new period. Periods are emitted
// strictly in stamp order: the oldest one as soon as every lidar has delivered, or, incomplete,
// as soon as each missing lidar has delivered a scan of a later period (a lidar's own scans come
// in order) or a scan stamped more than max_wait after its anchor has arrived (a lidar that stops
// sending delays the others by max_wait, never blocks them; the missing lidar is counted). Newer
// complete periods wait behind an older pending one so stamps stay increasing. A scan of a period
// already emitted is dropped and counted as late. Points keep their order: lidar by lidar in mount
// order (not arrival order), so the merged scan does not depend on the delivery order.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"

namespace statebench::est {

struct LidarMount {
  std::string id;   // header.sensor_id of its scans
  SE3 T_ref_lidar;  // lidar frame -> reference frame
};

struct LidarScanMergerOptions {
  TimeNs period_ns = 100'000'000;    // scan period of the lidars (10 Hz)
  TimeNs max_wait_ns = 100'000'000;  // how far the stream may run ahead of an incomplete period
  std::string merged_id = "merged";  // header.sensor_id of the merged scans
};

struct LidarScanMergerDiagnostics {
  std::size_t scans_in = 0;
  std::size_t merged = 0;      // merged scans emitted
  std::size_t incomplete = 0;  // of which at least one lidar was missing
  std::size_t late = 0;        // dropped: their period had already been emitted
  std::size_t duplicates = 0;  // dropped: a second scan of one lidar in one period
  std::size_t unknown = 0;     // dropped: sensor id not among the mounts
  std::map<std::string, std::size_t> scans_per_lidar;    // merged, per lidar
  std::map<std::string, std::size_t> missing_per_lidar;  // periods emitted without it
};

class LidarScanMerger {
 public:
  // Throws InputError when mounts is empty, an id repeats, or the period is not positive.
  LidarScanMerger(std::vector<LidarMount> mounts, const LidarScanMergerOptions& options = {});

  // Adds one lidar's scan; returns the merged scans it completes (oldest first, often none).
  std::vector<LidarScan> Add(const LidarScan& scan);
  // End of stream: every pending period, merged with what it has.
  std::vector<LidarScan> Flush();

  const LidarScanMergerDiagnostics& diagnostics() const { return diagnostics_; }
  const std::vector<LidarMount>& mounts() const { return mounts_; }

 private:
  struct Period {
    TimeNs anchor_ns = 0;
    std::vector<LidarScan> scans;  // one slot per mount; present[i] says if filled
    std::vector<char> present;
    std::size_t count = 0;
  };

  int MountIndex(const std::string& id) const;
  LidarScan Merge(const Period& period);
  void EmitReady(TimeNs newest_stamp_ns, bool flush, std::vector<LidarScan>* out);

  std::vector<LidarMount> mounts_;
  LidarScanMergerOptions options_;
  std::vector<Period> pending_;  // ascending anchors
  bool emitted_any_ = false;
  TimeNs last_emitted_anchor_ns_ = 0;
  TimeNs newest_stamp_ns_ = 0;
  std::vector<TimeNs> newest_per_lidar_ns_;  // newest stamp each lidar delivered (min: none)
  LidarScanMergerDiagnostics diagnostics_;
};

}  // namespace statebench::est
