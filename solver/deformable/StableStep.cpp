// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/StableStep.hpp"

#include <algorithm>
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
  StableStepEstimate out;
  out.safety = safety;
  out.lengthMin = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    const double l = elementLength(mesh, e);
    if (l < out.lengthMin) {
      out.lengthMin = l;
      out.element = e;
    }
  }
  out.waveSpeed = dilatationalWaveSpeed(material);
  out.dampingRatio = 2.0 * material.viscosity / (material.density * out.waveSpeed * out.lengthMin);
  const double xi = out.dampingRatio;
  out.contactFrequency = contactFrequency;
  const double omegaElement = 2.0 * out.waveSpeed / out.lengthMin;
  const double omega = std::sqrt(omegaElement * omegaElement + contactFrequency * contactFrequency);
  out.dt = safety * (2.0 / omega) * (std::sqrt(1.0 + xi * xi) - xi);
  return out;
}

} // namespace armour::deformable
