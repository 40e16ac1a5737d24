#include "sensors/gnss_velocity_joiner.hpp"

#include <cstdlib>
#include <utility>

namespace statebench::sensors {

void GnssVelocityJoiner::AddFix(const std::string& id, TimeNs stamp_ns, TimeNs received_ns,
                                Write write) {
  if (const auto held = fixes_.find(id); held != fixes_.end()) {  // its velocity never came
    const Write earlier = std::move(held->second.write);
    fixes_.erase(held);
    earlier(std::nullopt);
  }
  std::deque<HeldVelocity>& velocities = velocities_[id];
  auto best = velocities.end();
  for (auto it = velocities.begin(); it != velocities.end(); ++it) {
    const TimeNs gap = std::llabs(it->stamp_ns - stamp_ns);
    if (gap <= kMaxStampGapNs &&
        (best == velocities.end() || gap < std::llabs(best->stamp_ns - stamp_ns))) {
      best = it;
    }
  }
  if (best != velocities.end()) {
    const GnssVelocity velocity = best->velocity;
    velocities.erase(velocities.begin(), std::next(best));  // older ones belong to no later fix
    ++joined_[id];
    write(velocity);
    return;
  }
  fixes_[id] = HeldFix{stamp_ns, received_ns, std::move(write)};
}

bool GnssVelocityJoiner::AddVelocity(const std::string& id, TimeNs stamp_ns,
                                     const GnssVelocity& velocity) {
  if (const auto held = fixes_.find(id);
      held != fixes_.end() && std::llabs(held->second.stamp_ns - stamp_ns) <= kMaxStampGapNs) {
    const Write write = std::move(held->second.write);
    fixes_.erase(held);
    ++joined_[id];
    write(velocity);
    return true;
  }
  std::deque<HeldVelocity>& velocities = velocities_[id];
  velocities.push_back({stamp_ns, velocity});
  if (velocities.size() > kMaxHeldVelocities) velocities.pop_front();
  return false;
}

void GnssVelocityJoiner::Advance(TimeNs received_ns) {
  for (auto it = fixes_.begin(); it != fixes_.end();) {
    if (received_ns - it->second.received_ns <= kWaitNs) {
      ++it;
      continue;
    }
    const Write write = std::move(it->second.write);
    it = fixes_.erase(it);
    write(std::nullopt);
  }
}

void GnssVelocityJoiner::Flush() {
  while (!fixes_.empty()) {
    const Write write = std::move(fixes_.begin()->second.write);
    fixes_.erase(fixes_.begin());
    write(std::nullopt);
  }
}

std::size_t GnssVelocityJoiner::joined(const std::string& id) const {
  const auto it = joined_.find(id);
  return it == joined_.end() ? 0 : it->second;
}

}  // namespace statebench::sensors
