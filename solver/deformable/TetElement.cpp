// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/TetElement.hpp"

#include <Eigen/LU>

#include <cmath>

namespace armour::deformable {
namespace {

/// Barycentric coordinates (L1..L4) of a reference point and their derivatives dL/dxi (rows).
std::array<double, 4> barycentric(const Vec3& xi) { return {1.0 - xi.sum(), xi.x(), xi.y(), xi.z()}; }
const Eigen::Matrix<double, 4, 3, Eigen::RowMajor>& barycentricDerivatives() {
  static const Eigen::Matrix<double, 4, 3, Eigen::RowMajor> d =
      (Eigen::Matrix<double, 4, 3, Eigen::RowMajor>() << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
  return d;
}

Mat3 deformationGradient(const NodeMatrix& x, const NodeMatrix& gradient) { return x.transpose() * gradient; }

} // namespace

QuadratureRule quadratureRule(ElementOrder order) {
  QuadratureRule rule;
  if (order == ElementOrder::Linear) {
    rule.points = 1;
    rule.xi[0] = Vec3::Constant(0.25);
    rule.weight[0] = 1.0 / 6.0;
    return rule;
  }
  // 4-point Gauss rule, exact for quadratic polynomials: a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20.
  const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
  const double b = (5.0 - std::sqrt(5.0)) / 20.0;
  rule.points = 4;
  rule.xi = {Vec3(b, b, b), Vec3(a, b, b), Vec3(b, a, b), Vec3(b, b, a)};
  rule.weight = {1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0};
  return rule;
}

NodeVector shapeValues(ElementOrder order, const Vec3& xi) {
  const auto L = barycentric(xi);
  NodeVector N(nodesPerElement(order));
  for (int i = 0; i < 4; ++i) {
    N[i] = order == ElementOrder::Linear ? L[i] : L[i] * (2.0 * L[i] - 1.0);
  }
  if (order == ElementOrder::Quadratic) {
    for (int e = 0; e < 6; ++e) {
      N[4 + e] = 4.0 * L[kTet10Edges[e][0]] * L[kTet10Edges[e][1]];
    }
  }
  return N;
}

NodeMatrix shapeDerivatives(ElementOrder order, const Vec3& xi) {
  const auto& dL = barycentricDerivatives();
  NodeMatrix dN(nodesPerElement(order), 3);
  if (order == ElementOrder::Linear) {
    dN = dL;
    return dN;
  }
  const auto L = barycentric(xi);
  for (int i = 0; i < 4; ++i) {
    dN.row(i) = (4.0 * L[i] - 1.0) * dL.row(i);
  }
  for (int e = 0; e < 6; ++e) {
    const int a = kTet10Edges[e][0];
    const int b = kTet10Edges[e][1];
    dN.row(4 + e) = 4.0 * (L[a] * dL.row(b) + L[b] * dL.row(a));
  }
  return dN;
}

bool elementGeometry(ElementOrder order, const NodeMatrix& X, ElementGeometry& out) {
  const auto rule = quadratureRule(order);
  out.points = rule.points;
  out.volume = 0.0;
  const auto toPhysical = [&](const Vec3& xi, NodeMatrix& gradient, double& detJ) {
    const NodeMatrix dN = shapeDerivatives(order, xi);
    const Mat3 J = X.transpose() * dN; // dX/dxi
    detJ = J.determinant();
    if (!(detJ > 0.0)) {
      return false;
    }
    gradient = dN * J.inverse();
    return true;
  };
  for (int q = 0; q < rule.points; ++q) {
    double detJ = 0.0;
    if (!toPhysical(rule.xi[q], out.gradient[q], detJ)) {
      return false;
    }
    out.weight[q] = rule.weight[q] * detJ;
    out.volume += out.weight[q];
  }
  double detJ = 0.0;
  return toPhysical(Vec3::Constant(0.25), out.centroidGradient, detJ);
}

namespace {

/// The force kernel with the node count fixed at compile time (4 or 10), so Eigen unrolls the
/// small products; x, v and force are row-major N x 3 arrays.
template <int N>
bool internalForcesFixed(const ElementGeometry& g, const ElementModel& model, const double* xData,
                         const double* vData, double* forceData) {
  using Rows = Eigen::Matrix<double, N, 3, Eigen::RowMajor>;
  const Eigen::Map<const Rows> x(xData);
  const Eigen::Map<const Rows> v(vData);
  Eigen::Map<Rows> force(forceData);
  force.setZero();
  const auto gradient = [&](const NodeMatrix& m) { return Eigen::Map<const Rows>(m.data()); };
  const bool useFBar = model.fBar && g.points > 1;
  Rows g0;
  double J0 = 0.0;
  if (useFBar) {
    const Mat3 F0 = x.transpose() * gradient(g.centroidGradient);
    J0 = F0.determinant();
    if (!(J0 > 0.0)) {
      return false;
    }
    g0.noalias() = gradient(g.centroidGradient) * F0.inverse();
  }
  for (int q = 0; q < g.points; ++q) {
    const auto G = gradient(g.gradient[q]);
    const Mat3 F = x.transpose() * G;
    const double J = F.determinant();
    if (!(J > 0.0)) {
      return false;
    }
    const Mat3 Finv = F.inverse();
    const Rows gq = G * Finv; // spatial gradients dN/dx
    if (useFBar) {
      const Mat3 tau = kirchhoffStress(std::cbrt(J0 / J) * F, model.lame);
      force.noalias() += g.weight[q] * (gq * tau + (tau.trace() / 3.0) * (g0 - gq));
    } else {
      force.noalias() += g.weight[q] * (gq * kirchhoffStress(F, model.lame));
    }
    if (model.viscosity != 0.0) {
      const Mat3 L = (v.transpose() * G) * Finv;
      force.noalias() += (g.weight[q] * J * model.viscosity) * (gq * (L + L.transpose()));
    }
  }
  return true;
}

} // namespace

bool internalForces(const ElementGeometry& g, const ElementModel& model, const double* x, const double* v,
                    int nodes, double* force) {
  return nodes == 4 ? internalForcesFixed<4>(g, model, x, v, force) : internalForcesFixed<10>(g, model, x, v, force);
}

bool internalForces(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x, const NodeMatrix& v,
                    NodeMatrix& force) {
  force.resize(x.rows(), 3);
  return internalForces(g, model, x.data(), v.data(), static_cast<int>(x.rows()), force.data());
}

double elementStrainEnergy(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x) {
  const bool useFBar = model.fBar && g.points > 1;
  const double J0 = useFBar ? deformationGradient(x, g.centroidGradient).determinant() : 0.0;
  double energy = 0.0;
  for (int q = 0; q < g.points; ++q) {
    const Mat3 F = deformationGradient(x, g.gradient[q]);
    const double J = F.determinant();
    if (!(J > 0.0) || (useFBar && !(J0 > 0.0))) {
      return std::nan("");
    }
    energy += g.weight[q] * strainEnergyDensity(useFBar ? Mat3(std::cbrt(J0 / J) * F) : F, model.lame);
  }
  return energy;
}

Mat3 elementCauchyStress(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& x,
                         const NodeMatrix& v) {
  const bool useFBar = model.fBar && g.points > 1;
  const double J0 = useFBar ? deformationGradient(x, g.centroidGradient).determinant() : 0.0;
  Mat3 sum = Mat3::Zero();
  double volume = 0.0;
  for (int q = 0; q < g.points; ++q) {
    const Mat3 F = deformationGradient(x, g.gradient[q]);
    const double J = F.determinant();
    const Mat3 Fbar = useFBar ? Mat3(std::cbrt(J0 / J) * F) : F;
    // Elastic part from F_bar (its determinant is J0 under F-bar), viscous part from the point's F.
    Mat3 T = kirchhoffStress(Fbar, model.lame) / Fbar.determinant();
    if (model.viscosity != 0.0) {
      const Mat3 L = deformationGradient(v, g.gradient[q]) * F.inverse();
      T += model.viscosity * (L + L.transpose());
    }
    sum += (g.weight[q] * J) * T;
    volume += g.weight[q] * J;
  }
  return sum / volume;
}

Eigen::MatrixXd elementTangentAtRest(const ElementGeometry& g, const ElementModel& model, const NodeMatrix& X) {
  const int nen = static_cast<int>(X.rows());
  const int n = 3 * nen;
  Eigen::MatrixXd K(n, n);
  const NodeMatrix v = NodeMatrix::Zero(nen, 3);
  const double h = 1e-6 * std::cbrt(g.volume);
  NodeMatrix fp(nen, 3), fm(nen, 3);
  for (int j = 0; j < n; ++j) {
    NodeMatrix xp = X;
    NodeMatrix xm = X;
    xp(j / 3, j % 3) += h;
    xm(j / 3, j % 3) -= h;
    internalForces(g, model, xp, v, fp);
    internalForces(g, model, xm, v, fm);
    for (int i = 0; i < n; ++i) {
      K(i, j) = (fp(i / 3, i % 3) - fm(i / 3, i % 3)) / (2.0 * h);
    }
  }
  return 0.5 * (K + K.transpose());
}


} // namespace armour::deformable
