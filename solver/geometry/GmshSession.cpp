// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/GmshSession.hpp"

#include <gmsh.h>
#include <omp.h>

#include <mutex>
#include <unordered_map>

namespace armour::geometry {
namespace {

std::mutex& gmshMutex() {
  static std::mutex m;
  return m;
}

void initialiseOnce() {
  static bool initialised = false;
  if (!initialised) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
    initialised = true;
  }
}

} // namespace

struct GmshSession::Impl {
  std::unique_lock<std::mutex> lock{gmshMutex()};
  /// gmsh sets the process's OpenMP thread count from its General.NumThreads option (1 by default)
  /// when it initialises and meshes; the caller's count is put back when the session ends, or
  /// every later parallel region of the solver would run on one thread.
  int callerThreads = omp_get_max_threads();
};

GmshSession::GmshSession(const std::string& model) : impl_(std::make_unique<Impl>()) {
  initialiseOnce();
  // One thread inside gmsh, every session: its first initialisation leaves it at one, but later
  // sessions ran with the caller's count put back, and its meshing on 2 threads gave another mesh
  // (the second Core-Loc of a process differed from the first in every vertex; session 13), so a
  // shape built twice in one process, or an ensemble member after the first, was not reproducible.
  gmsh::option::setNumber("General.NumThreads", 1);
  omp_set_num_threads(1);
  gmsh::clear();
  gmsh::model::add(model);
}

GmshSession::~GmshSession() {
  gmsh::clear();
  omp_set_num_threads(impl_->callerThreads);
}

std::vector<GmshEntity> GmshSession::fuse(const std::vector<GmshEntity>& objects,
                                          const std::vector<GmshEntity>& tools) {
  std::vector<GmshEntity> out;
  std::vector<std::vector<GmshEntity>> map;
  gmsh::model::occ::fuse(objects, tools, out, map);
  return out;
}

std::vector<GmshEntity> GmshSession::cut(const std::vector<GmshEntity>& objects,
                                         const std::vector<GmshEntity>& tools) {
  std::vector<GmshEntity> out;
  std::vector<std::vector<GmshEntity>> map;
  gmsh::model::occ::cut(objects, tools, out, map);
  return out;
}

double GmshSession::occVolume(const std::vector<GmshEntity>& volumes) {
  double total = 0.0;
  for (const auto& [dim, tag] : volumes) {
    double mass = 0.0;
    gmsh::model::occ::getMass(dim, tag, mass);
    total += mass;
  }
  return total;
}

TriangleMesh GmshSession::meshSurface(double sizeMax, int elementsPerTwoPi) {
  gmsh::model::occ::synchronize();
  gmsh::option::setNumber("Mesh.MeshSizeMax", sizeMax);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0.0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", elementsPerTwoPi);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::model::mesh::generate(2);

  std::vector<std::size_t> nodeTags;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(nodeTags, coords, parametric);
  TriangleMesh mesh;
  std::unordered_map<std::size_t, std::int32_t> index;
  mesh.vertices.reserve(nodeTags.size());
  for (std::size_t i = 0; i < nodeTags.size(); ++i) {
    index[nodeTags[i]] = static_cast<std::int32_t>(mesh.vertices.size());
    mesh.vertices.emplace_back(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
  }
  std::vector<std::size_t> elementTags, elementNodes;
  gmsh::model::mesh::getElementsByType(2, elementTags, elementNodes); // 3-node triangles
  mesh.triangles.reserve(elementTags.size());
  for (std::size_t e = 0; e < elementTags.size(); ++e) {
    mesh.triangles.push_back({index.at(elementNodes[3 * e]), index.at(elementNodes[3 * e + 1]),
                              index.at(elementNodes[3 * e + 2])});
  }
  removeUnusedVertices(mesh);
  return mesh;
}

} // namespace armour::geometry
