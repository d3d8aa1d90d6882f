// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StableStep.hpp"

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>

namespace armour::deformable {

double elementLength(const DeformableMesh& mesh, std::size_t e) {
  const auto* n = mesh.element(e);
  const Vec3& a = mesh.nodes[n[0]];
  const Vec3& b = mesh.nodes[n[1]];
  const Vec3& c = mesh.nodes[n[2]];
  const Vec3& d = mesh.nodes[n[3]];
  const double volume = (b - a).dot((c - a).cross(d - a)) / 6.0;
  // Twice the face areas: the altitude onto face k is 3 V / area_k = 6 V / (2 area_k).
  const double twiceArea = std::max({(c - b).cross(d - b).norm(), (c - a).cross(d - a).norm(),
                                     (b - a).cross(d - a).norm(), (b - a).cross(c - a).norm()});
  const double altitude = 6.0 * volume / twiceArea;
  return altitude / (mesh.order == ElementOrder::Quadratic ? kQuadraticLengthDivisor : kLinearLengthDivisor);
}

StableStepEstimate stableStep(const DeformableMesh& mesh, const MaterialSettings& material, double safety,
                              double contactFrequency) {
  double lengthMin = std::numeric_limits<double>::infinity();
  std::size_t element = 0;
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    const double l = elementLength(mesh, e);
    if (l < lengthMin) {
      lengthMin = l;
      element = e;
    }
  }
  return stableStepForLength(lengthMin, element, material, safety, contactFrequency);
}

StableStepEstimate stableStepForLength(double lengthMin, std::size_t element, const MaterialSettings& material,
                                       double safety, double contactFrequency) {
  StableStepEstimate out;
  out.safety = safety;
  out.lengthMin = lengthMin;
  out.element = element;
  out.waveSpeed = dilatationalWaveSpeed(material);
  out.dampingRatio = 2.0 * material.viscosity / (material.density * out.waveSpeed * out.lengthMin);
  const double xi = out.dampingRatio;
  out.contactFrequency = contactFrequency;
  const double omegaElement = 2.0 * out.waveSpeed / out.lengthMin;
  const double omega = std::sqrt(omegaElement * omegaElement + contactFrequency * contactFrequency);
  out.dt = safety * (2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi);
  return out;
}

namespace {

/// The largest L for which scaling the elements `order` (sorted by length) shorter than L to L
/// adds at most `budget` of volume-equivalent (the added mass over rho).
double targetLength(const std::vector<std::size_t>& order, const std::vector<double>& length,
                    const std::vector<double>& volumes, double budget) {
  // With the k shortest scaled the added volume is L^2 sum V_i / l_i^2 - sum V_i.
  double sumV = 0.0, sumVoverL2 = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t e = order[k];
    sumV += volumes[e];
    sumVoverL2 += volumes[e] / (length[e] * length[e]);
    const double L = std::sqrt((budget + sumV) / sumVoverL2);
    const double next = k + 1 < order.size() ? length[order[k + 1]] : std::numeric_limits<double>::infinity();
    if (L <= next) {
      return std::max(L, length[e]);
    }
  }
  return std::numeric_limits<double>::infinity(); // (not reached: the last L is accepted)
}

} // namespace

Eigen::SparseMatrix<double> tangentAtRest(const DeformableMesh& mesh, const std::vector<ElementGeometry>& geometry,
                                          const ElementModel& model) {
  const int nen = mesh.nodesPerElement();
  const auto elements = static_cast<std::int64_t>(mesh.elementCount());
  std::vector<Eigen::MatrixXd> tangents(mesh.elementCount());
#pragma omp parallel for schedule(static)
  for (std::int64_t ei = 0; ei < elements; ++ei) {
    const auto e = static_cast<std::size_t>(ei);
    NodeMatrix X(nen, 3);
    for (int a = 0; a < nen; ++a) X.row(a) = mesh.nodes[mesh.element(e)[a]].transpose();
    tangents[e] = elementTangentAtRest(geometry[e], model, X);
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(mesh.elementCount() * static_cast<std::size_t>(9 * nen * nen));
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    for (int i = 0; i < 3 * nen; ++i) {
      for (int j = 0; j < 3 * nen; ++j) {
        triplets.emplace_back(3 * mesh.element(e)[i / 3] + i % 3, 3 * mesh.element(e)[j / 3] + j % 3, tangents[e](i, j));
      }
    }
  }
  const auto n = static_cast<Eigen::Index>(3 * mesh.nodeCount());
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

double meshFrequencyBound(const DeformableMesh& mesh, const std::vector<ElementGeometry>& geometry,
                          const ElementModel& model, const std::vector<double>& masses) {
  // Row sums of the assembled |K_ij| (a sum of element entries of both signs is smaller than the
  // sum of their sizes); K is symmetric, so its columns are its rows.
  const Eigen::SparseMatrix<double> K = tangentAtRest(mesh, geometry, model);
  double omega2 = 0.0;
  for (Eigen::Index c = 0; c < K.outerSize(); ++c) {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) sum += std::abs(it.value());
    omega2 = std::max(omega2, sum / masses[static_cast<std::size_t>(c / 3)]);
  }
  return std::sqrt(omega2);
}

MassScaling massScaling(const DeformableMesh& mesh, const std::vector<double>& volumes, double density,
                        double maxAddedFraction) {
  const std::size_t n = mesh.elementCount();
  MassScaling out;
  out.factor.assign(n, 1.0);
  std::vector<double> length(n);
  double volume = 0.0;
  out.lengthMin = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < n; ++e) {
    length[e] = elementLength(mesh, e);
    volume += volumes[e];
    if (length[e] < out.lengthMin) {
      out.lengthMin = length[e];
      out.element = e;
    }
  }
  out.mass = density * volume;
  out.length = out.lengthMin;
  if (!(maxAddedFraction > 0.0)) {
    return out;
  }
  // The budget is each body's (each disconnected part of the mesh: a unit and its anvil get a
  // fraction of their own mass each); the step is set by the part whose L is the shortest, and the
  // others scale to that L only.
  std::size_t parts = 0;
  const std::vector<std::int32_t> nodePart = nodeParts(mesh, parts);
  std::vector<std::vector<std::size_t>> byPart(parts);
  std::vector<double> partVolume(parts, 0.0);
  for (std::size_t e = 0; e < n; ++e) {
    const auto p = static_cast<std::size_t>(nodePart[static_cast<std::size_t>(mesh.element(e)[0])]);
    byPart[p].push_back(e);
    partVolume[p] += volumes[e];
  }
  out.length = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < parts; ++p) {
    if (byPart[p].empty()) continue; // (a lone node: makeDeformableMesh leaves none)
    // Ties broken by index: the same order, and so the same bits, on every machine.
    std::sort(byPart[p].begin(), byPart[p].end(), [&](std::size_t a, std::size_t b) {
      return length[a] < length[b] || (length[a] == length[b] && a < b);
    });
    out.length = std::min(out.length, targetLength(byPart[p], length, volumes, maxAddedFraction * partVolume[p]));
  }
  std::vector<double> partAdded(parts, 0.0);
  for (std::size_t e = 0; e < n; ++e) {
    if (length[e] < out.length) {
      out.factor[e] = (out.length / length[e]) * (out.length / length[e]);
      const double added = (out.factor[e] - 1.0) * density * volumes[e];
      out.addedMass += added;
      partAdded[static_cast<std::size_t>(nodePart[static_cast<std::size_t>(mesh.element(e)[0])])] += added;
      ++out.scaled;
    }
  }
  for (std::size_t p = 0; p < parts; ++p) {
    if (partVolume[p] > 0.0) {
      out.largestPartFraction = std::max(out.largestPartFraction, partAdded[p] / (density * partVolume[p]));
    }
  }
  return out;
}

} // namespace armour::deformable
