// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/QuasiStatic.hpp"

#include "core/Error.hpp"
#include "deformable/HalfSpaceContact.hpp"
#include "deformable/StableStep.hpp"
#include "deformable/SurfaceLoads.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace armour::deformable {

QuasiStaticUnit::QuasiStaticUnit(const DeformableBody& body) : body_(body) {
  const DeformableMesh& mesh = body.mesh();
  const std::size_t nodes = mesh.nodeCount();
  std::size_t parts = 0;
  (void)nodeParts(mesh, parts);
  if (parts != 1) {
    core::failInput(body.source(), "its mesh holds {} bodies; the quasi-static stress takes one unit at a time "
                    "(mesh each unit on its own)",
                    parts);
  }
  const auto& masses = body.masses();
  for (std::size_t a = 0; a < nodes; ++a) {
    mass_ += masses[a];
    centre_ += masses[a] * mesh.nodes[a];
  }
  centre_ /= mass_;
  for (std::size_t a = 0; a < nodes; ++a) {
    const Vec3 r = mesh.nodes[a] - centre_;
    inertia_ += masses[a] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }

  stiffness_ = tangentAtRest(mesh, body.geometry(), body.model());
  double diagonal = stiffness_.diagonal().sum();
  std::vector<Eigen::Triplet<double>> triplets;
  diagonal /= static_cast<double>(3 * nodes);
  // The six rigid modes held by soft springs at three far-apart nodes: A in all directions, B
  // across AB, C across the plane ABC. The loads are balanced, so the springs carry no force.
  const auto farthestFrom = [&](const Vec3& p) {
    std::size_t best = 0;
    for (std::size_t a = 1; a < mesh.cornerCount; ++a) {
      if ((mesh.nodes[a] - p).squaredNorm() > (mesh.nodes[best] - p).squaredNorm()) best = a;
    }
    return best;
  };
  const std::size_t A = farthestFrom(centre_);
  const std::size_t B = farthestFrom(mesh.nodes[A]);
  const Vec3 ab = (mesh.nodes[B] - mesh.nodes[A]).normalized();
  std::size_t C = A;
  double offLine = -1.0;
  for (std::size_t a = 0; a < mesh.cornerCount; ++a) {
    const double d = (mesh.nodes[a] - mesh.nodes[A]).cross(ab).norm();
    if (d > offLine) {
      offLine = d;
      C = a;
    }
  }
  const Vec3 normal = ab.cross(mesh.nodes[C] - mesh.nodes[A]).normalized();
  const auto spring = [&](std::size_t node, const Mat3& k) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        triplets.emplace_back(static_cast<int>(3 * node) + i, static_cast<int>(3 * node) + j, diagonal * k(i, j));
  };
  spring(A, Mat3::Identity());
  spring(B, Mat3::Identity() - ab * ab.transpose());
  spring(C, normal * normal.transpose());
  Eigen::SparseMatrix<double> springs(stiffness_.rows(), stiffness_.cols());
  springs.setFromTriplets(triplets.begin(), triplets.end());
  stiffness_ += springs;
  factor_ = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(stiffness_);
  if (factor_->info() != Eigen::Success) {
    core::failInput(body.source(), "the stiffness of its mesh cannot be factored ({} nodes): the mesh must be one "
                    "connected body without inverted elements; mesh the unit again",
                    nodes);
  }

  const auto triangles = surfaceTriangles(mesh, boundaryFaces(mesh));
  const auto area = tributaryAreas(mesh, triangles);
  for (std::size_t a = 0; a < nodes; ++a) {
    if (area[a] > 0.0) {
      surfaceNodes_.push_back(a);
      surfaceArea_.push_back(area[a]);
    }
  }
}

std::vector<Vec3> QuasiStaticUnit::spread(const std::vector<PointLoad>& loads, double radius,
                                          std::size_t minNodes) const {
  const auto& nodes = body_.mesh().nodes;
  std::vector<Vec3> f(nodes.size(), Vec3::Zero());
  const std::size_t count = surfaceNodes_.size();
  std::vector<double> distance(count), sorted(count);
  for (const PointLoad& load : loads) {
    for (std::size_t k = 0; k < count; ++k) distance[k] = (nodes[surfaceNodes_[k]] - load.point).norm();
    // At least minNodes nodes share a load: on a coarse mesh the radius grows to 1.5 times the
    // distance of the minNodes-th nearest surface node (one node alone would take a point load,
    // whose stress has no limit).
    double r = radius;
    const std::size_t need = std::clamp<std::size_t>(minNodes, 1, count);
    sorted = distance;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(need - 1), sorted.end());
    if (sorted[need - 1] >= r) r = 1.5 * sorted[need - 1];
    double sum = 0.0;
    for (std::size_t k = 0; k < count; ++k) sum += distance[k] < r ? surfaceArea_[k] * (1.0 - distance[k] / r) : 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      if (distance[k] < r) f[surfaceNodes_[k]] += (surfaceArea_[k] * (1.0 - distance[k] / r) / sum) * load.force;
    }
  }
  return f;
}

QuasiStaticResult QuasiStaticUnit::solve(const std::vector<PointLoad>& loads, const Vec3& omega, double radius,
                                         std::size_t minNodes) const {
  const DeformableMesh& mesh = body_.mesh();
  const auto& masses = body_.masses();
  const std::size_t nodes = mesh.nodeCount();
  std::vector<Vec3> f = spread(loads, radius, minNodes);
  // Inertia relief on the lumped masses: m a = F; J alpha = M - sum m r x (omega x (omega x r)).
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();
  double largest = 0.0;
  for (std::size_t a = 0; a < nodes; ++a) {
    const Vec3 r = mesh.nodes[a] - centre_;
    const Vec3 centrifugal = masses[a] * omega.cross(omega.cross(r));
    force += f[a];
    moment += r.cross(f[a]) - r.cross(centrifugal);
  }
  QuasiStaticResult out;
  out.acceleration = force / mass_;
  out.angularAcceleration = inertia_.ldlt().solve(moment);
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(3 * nodes));
  Vec3 sum = Vec3::Zero(), turn = Vec3::Zero();
  for (std::size_t a = 0; a < nodes; ++a) {
    const Vec3 r = mesh.nodes[a] - centre_;
    const Vec3 total =
        f[a] - masses[a] * (out.acceleration + out.angularAcceleration.cross(r) + omega.cross(omega.cross(r)));
    rhs.segment<3>(static_cast<Eigen::Index>(3 * a)) = total;
    sum += total;
    turn += r.cross(total);
    largest = std::max(largest, total.norm());
  }
  const double size = std::sqrt(inertia_.trace() / (2.0 * mass_)); // radius of gyration (unit: m)
  out.imbalance = largest > 0.0 ? (sum.norm() + turn.norm() / size) / largest : 0.0;
  const Eigen::VectorXd u = factor_->solve(rhs);
  out.displacement.resize(nodes);
  for (std::size_t a = 0; a < nodes; ++a) out.displacement[a] = u.segment<3>(static_cast<Eigen::Index>(3 * a));
  const int nen = mesh.nodesPerElement();
  out.stress.resize(mesh.elementCount());
  const auto elements = static_cast<std::int64_t>(mesh.elementCount());
#pragma omp parallel for schedule(static)
  for (std::int64_t ei = 0; ei < elements; ++ei) {
    const auto e = static_cast<std::size_t>(ei);
    NodeMatrix x(nen, 3);
    for (int a = 0; a < nen; ++a) {
      const auto node = static_cast<std::size_t>(mesh.element(e)[a]);
      x.row(a) = (mesh.nodes[node] + out.displacement[node]).transpose();
    }
    out.stress[e] = elementCauchyStress(body_.geometry()[e], body_.model(), x, NodeMatrix::Zero(nen, 3));
  }
  return out;
}

} // namespace armour::deformable
