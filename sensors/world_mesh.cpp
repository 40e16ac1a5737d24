#include "sensors/world_mesh.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace statebench::sensors {

int TriangleMesh::AddVertex(const Vec3& v) {
  vertices.push_back(v);
  return static_cast<int>(vertices.size()) - 1;
}

void TriangleMesh::AddTriangle(int a, int b, int c, SurfaceMaterial material) {
  triangles.push_back({a, b, c});
  materials.push_back(material);
}

void TriangleMesh::AddBox(const WorldBox& box) {
  const Mat3 r = Eigen::AngleAxisd(box.yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 half = 0.5 * box.size_m;
  int v[8];
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                      (i & 4) ? half.z() : -half.z());
    v[i] = AddVertex(box.centre_world + r * corner);
  }
  // Faces as quads (corner indices by bits x=1, y=2, z=4), counter-clockwise from outside.
  static constexpr int kQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : kQuads) {
    AddTriangle(v[q[0]], v[q[1]], v[q[2]], box.material);
    AddTriangle(v[q[0]], v[q[2]], v[q[3]], box.material);
  }
}

void TriangleMesh::AddCylinder(const WorldCylinder& c, int sides) {
  const Vec3 up = c.height_m * Vec3::UnitZ();
  const int top_centre = AddVertex(c.base_world + up);
  int first = -1;
  for (int i = 0; i < sides; ++i) {
    const double a = 2.0 * std::numbers::pi * i / sides;
    const Vec3 rim = c.base_world + c.radius_m * Vec3(std::cos(a), std::sin(a), 0.0);
    const int bottom = AddVertex(rim);
    AddVertex(rim + up);
    if (i == 0) first = bottom;
  }
  for (int i = 0; i < sides; ++i) {
    const int b0 = first + 2 * i;
    const int b1 = first + 2 * ((i + 1) % sides);
    AddTriangle(b0, b1, b1 + 1, c.material);
    AddTriangle(b0, b1 + 1, b0 + 1, c.material);
    AddTriangle(top_centre, b0 + 1, b1 + 1, c.material);
  }
}

void TriangleMesh::AddSphere(const WorldSphere& s, int subdivisions) {
  // Icosahedron on the unit sphere, then each triangle split in four per level.
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> unit = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                            {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                            {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (Vec3& v : unit) v.normalize();
  std::vector<std::array<int, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      unit.push_back((unit[a] + unit[b]).normalized());
      const int id = static_cast<int>(unit.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  const int base = static_cast<int>(vertices.size());
  for (const Vec3& u : unit) AddVertex(s.centre_world + s.radius_m * u);
  for (const auto& f : faces) AddTriangle(base + f[0], base + f[1], base + f[2], s.material);
}

}  // namespace statebench::sensors
