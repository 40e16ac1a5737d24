// Triangle soup of the static lidar world in double precision, with one surface material per
// triangle. Primitives are tessellated here (boxes exactly; cylinders as prisms, spheres as
// subdivided icosahedra), so the mesh *is* the world surface the lidar sees.
#pragma once

#include <array>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/surface_material.hpp"
#include "sensors/world_layout.hpp"

namespace statebench::sensors {

struct TriangleMesh {
  std::vector<Vec3> vertices;  // world frame, m
  std::vector<std::array<int, 3>>
      triangles;                           // outward-facing (counter-clockwise seen from outside)
  std::vector<SurfaceMaterial> materials;  // one per triangle

  int AddVertex(const Vec3& v);
  void AddTriangle(int a, int b, int c, SurfaceMaterial material);
  void AddBox(const WorldBox& box);
  void AddCylinder(const WorldCylinder& cylinder, int sides);
  void AddSphere(const WorldSphere& sphere, int subdivisions);
  std::size_t size() const { return triangles.size(); }
};

}  // namespace statebench::sensors
