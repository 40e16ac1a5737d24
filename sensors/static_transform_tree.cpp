#include "sensors/static_transform_tree.hpp"

namespace statebench::sensors {

void StaticTransformTree::Set(const std::string& parent, const std::string& child,
                              const SE3& T_parent_child) {
  parent_of_[child] = Edge{parent, T_parent_child};
}

std::optional<std::map<std::string, SE3>> StaticTransformTree::Ancestors(
    const std::string& frame) const {
  std::map<std::string, SE3> out;
  out.emplace(frame, SE3::Identity());
  std::string f = frame;
  std::optional<SE3> T_ancestor_frame;  // composed only from real edges (exact for one edge)
  while (true) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) return out;
    const Edge& e = it->second;
    T_ancestor_frame = T_ancestor_frame ? e.T_parent_child * *T_ancestor_frame : e.T_parent_child;
    if (!out.emplace(e.parent, *T_ancestor_frame).second) return std::nullopt;  // a loop
    f = e.parent;
  }
}

std::optional<SE3> StaticTransformTree::Lookup(const std::string& a, const std::string& b) const {
  if (a == b) return SE3::Identity();
  const auto up_b = Ancestors(b);
  if (!up_b) return std::nullopt;
  if (const auto it = up_b->find(a); it != up_b->end()) return it->second;  // a above b
  const auto up_a = Ancestors(a);
  if (!up_a) return std::nullopt;
  if (const auto it = up_a->find(b); it != up_a->end()) return it->second.Inverse();
  // Through a common ancestor c: T_a_b = T_c_a^-1 T_c_b.
  for (const auto& [frame, T_c_a] : *up_a) {
    if (const auto it = up_b->find(frame); it != up_b->end()) {
      return T_c_a.Inverse() * it->second;
    }
  }
  return std::nullopt;
}

}  // namespace statebench::sensors
