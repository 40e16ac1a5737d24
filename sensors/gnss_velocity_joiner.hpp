// Joins a receiver's velocity to its position fixes when the two come as separate messages (a
// ROS bag: NavSatFix on one topic, the Doppler velocity as a twist on another, each stamped by
// the driver when its NMEA sentence arrived). A velocity belongs to the fix of the same receiver
// whose stamp is nearest, within kMaxStampGapNs; either may come first. A fix waits for its
// velocity until the input (receive time) is kWaitNs past it, then goes out without one. Fixes
// of one receiver go out in the order they came. (Header compiled as C++17 too: the bag import.)
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "core/measurements.hpp"

namespace statebench::sensors {

class GnssVelocityJoiner {
 public:
  static constexpr TimeNs kMaxStampGapNs = 50 * kNsPerMillisecond;
  static constexpr TimeNs kWaitNs = 500 * kNsPerMillisecond;
  // Writes a fix, with the velocity joined to it or none.
  using Write = std::function<void(const std::optional<GnssVelocity>& velocity)>;

  // A fix of receiver `id` stamped stamp_ns, received at received_ns (non-decreasing over all
  // calls); `write` is called once, now or later (Advance, Flush).
  void AddFix(const std::string& id, TimeNs stamp_ns, TimeNs received_ns, Write write);
  // A velocity of receiver `id`; true if it was joined to a fix now (else it is kept for a
  // later fix and may never be used).
  bool AddVelocity(const std::string& id, TimeNs stamp_ns, const GnssVelocity& velocity);
  // Writes the fixes that waited kWaitNs of receive time without a velocity.
  void Advance(TimeNs received_ns);
  // Writes every waiting fix (the input ended).
  void Flush();

  // Velocities joined to a fix, per receiver.
  std::size_t joined(const std::string& id) const;

 private:
  struct HeldFix {
    TimeNs stamp_ns = 0;
    TimeNs received_ns = 0;
    Write write;
  };
  struct HeldVelocity {
    TimeNs stamp_ns = 0;
    GnssVelocity velocity;
  };
  static constexpr std::size_t kMaxHeldVelocities = 16;

  std::map<std::string, HeldFix> fixes_;  // at most one waiting fix per receiver
  std::map<std::string, std::deque<HeldVelocity>> velocities_;
  std::map<std::string, std::size_t> joined_;
};

}  // namespace statebench::sensors
