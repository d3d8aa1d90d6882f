// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/UnitStress.hpp"

#include "deformable/DeformableVtu.hpp"
#include "deformable/StressFields.hpp"
#include "geometry/Tetrahedralizer.hpp"

#include <limits>

namespace armour::deformable {

UnitStressModel::UnitStressModel(const geometry::TriangleMesh& surface, const UnitStressSettings& settings,
                                 const std::string& source)
    : settings_(settings) {
  geometry::TetrahedralizeOptions options;
  options.targetTetCount = settings.tets;
  options.keepSurface = false;
  options.source = source;
  const geometry::TetMesh tets = geometry::tetrahedralize(surface, options);
  DeformableSettings body;
  body.material = settings.material;
  body_ = std::make_unique<DeformableBody>(makeDeformableMesh(tets, settings.order, source.c_str()), body, source);
  unit_ = std::make_unique<QuasiStaticUnit>(*body_);
  const DeformableMesh& mesh = body_->mesh();
  centroids_.resize(mesh.elementCount());
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    Vec3 c = Vec3::Zero();
    for (int a = 0; a < 4; ++a) c += mesh.nodes[static_cast<std::size_t>(mesh.element(e)[a])];
    centroids_[e] = 0.25 * c;
  }
}

UnitStressModel::~UnitStressModel() = default;

std::size_t UnitStressModel::elementCount() const { return body_->mesh().elementCount(); }

QuasiStaticResult UnitStressModel::solve(const UnitLoadCase& c) const {
  return unit_->solve(c.loads, c.angularVelocity, settings_.spreadRadius);
}

void UnitStressModel::writeVtu(const UnitLoadCase& c, const std::filesystem::path& path) {
  const QuasiStaticResult r = solve(c);
  const auto& reference = body_->mesh().nodes;
  std::vector<Vec3> posed(reference.size());
  for (std::size_t a = 0; a < reference.size(); ++a) posed[a] = reference[a] + r.displacement[a];
  body_->setPositions(posed);
  // Restored even when the write throws: the model's later cases read the reference state.
  struct Restore {
    DeformableBody& body;
    const std::vector<Vec3>& reference;
    ~Restore() { body.setPositions(reference); }
  } restore{*body_, reference};
  writeDeformableVtu(*body_, path);
}

UnitStressResult UnitStressModel::evaluate(const UnitLoadCase& c) const {
  const QuasiStaticResult r = solve(c);
  UnitStressResult out;
  out.imbalance = r.imbalance;
  out.sigma1 = out.sigma1Away = out.differential = -std::numeric_limits<double>::infinity();
  const double away2 = settings_.awayDistance * settings_.awayDistance;
  bool anyAway = false;
  for (std::size_t e = 0; e < r.stress.size(); ++e) {
    const StressSummary s = summarizeStress(r.stress[e]);
    if (s.principal.x() > out.sigma1) {
      out.sigma1 = s.principal.x();
      out.where = centroids_[e];
    }
    out.differential = std::max(out.differential, s.differential);
    bool away = true;
    for (const PointLoad& l : c.loads) {
      if ((l.point - centroids_[e]).squaredNorm() <= away2) {
        away = false;
        break;
      }
    }
    if (away && s.principal.x() > out.sigma1Away) {
      out.sigma1Away = s.principal.x();
      out.whereAway = centroids_[e];
      anyAway = true;
    }
  }
  if (!anyAway) out.sigma1Away = 0.0;
  return out;
}

} // namespace armour::deformable
