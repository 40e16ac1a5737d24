// The static transforms between named frames (ROS tf: /tf_static of a bag plus those a topic map
// adds) as a tree of child -> parent edges, and the transform between any two connected frames.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "core/se3.hpp"

namespace statebench::sensors {

class StaticTransformTree {
 public:
  // The edge parent <- child; a later edge of the same child replaces the earlier one (tf2's
  // rule for /tf_static).
  void Set(const std::string& parent, const std::string& child, const SE3& T_parent_child);

  // T_a_b (maps frame-b points into frame a), nullopt when the frames are not connected (or the
  // edges form a loop). A frame is connected to itself even when no edge names it. A direct
  // edge is returned as it was set, bit for bit.
  std::optional<SE3> Lookup(const std::string& a, const std::string& b) const;

  std::size_t size() const { return parent_of_.size(); }

 private:
  struct Edge {
    std::string parent;
    SE3 T_parent_child;
  };
  // T_ancestor_frame for every ancestor of `frame` (frame itself included, identity), or nullopt
  // on a loop.
  std::optional<std::map<std::string, SE3>> Ancestors(const std::string& frame) const;

  std::map<std::string, Edge> parent_of_;
};

}  // namespace statebench::sensors
