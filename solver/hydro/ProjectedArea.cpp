// SPDX-License-Identifier: GPL-3.0-or-later
#include "hydro/ProjectedArea.hpp"

#include "core/Error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace armour::hydro {
namespace {

/// tan(pi xi / 4) for the node parameter xi = k / m (k = -m .. m), with the values at xi = 0 and
/// xi = +-1 exact, so that the directions of nodes shared by two faces are bit-identical.
double nodeTangent(int k, int m) {
  if (k == 0) {
    return 0.0;
  }
  if (k == m) {
    return 1.0;
  }
  if (k == -m) {
    return -1.0;
  }
  return std::tan(0.25 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(m));
}

/// The two axes other than a, in increasing order.
std::array<int, 2> otherAxes(int a) {
  return a == 0 ? std::array<int, 2>{1, 2} : (a == 1 ? std::array<int, 2>{0, 2} : std::array<int, 2>{0, 1});
}

/// d or -d, whichever has its first non-zero component positive: A(d) = A(-d), and computing every
/// node from this representative makes the values of antipodal and shared nodes bit-identical.
Vec3 canonical(const Vec3& d) {
  for (int k = 0; k < 3; ++k) {
    if (d[k] != 0.0) {
      return d[k] > 0.0 ? d : Vec3(-d);
    }
  }
  return d;
}

} // namespace

double convexProjectedArea(const geometry::TriangleMesh& mesh, const Vec3& direction) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    sum += std::abs(mesh.doubleAreaNormal(t).dot(direction)); // 2 a |n . d|
  }
  return 0.25 * sum;
}

double rasterisedProjectedArea(const geometry::TriangleMesh& mesh, const Vec3& direction, int resolution) {
  const Vec3 d = direction.normalized();
  // Image-plane axes: e1 along the cross product with the axis d is least aligned with, so that a
  // direction along a body axis gets image axes along the other two (a box seen face-on then fills
  // its bounds exactly).
  int least = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(d[k]) < std::abs(d[least])) {
      least = k;
    }
  }
  const Vec3 e1 = d.cross(Vec3::Unit(least)).normalized();
  const Vec3 e2 = d.cross(e1);
  const std::size_t nv = mesh.vertexCount();
  std::vector<double> pu(nv), pv(nv);
  double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
  for (std::size_t i = 0; i < nv; ++i) {
    pu[i] = e1.dot(mesh.vertices[i]);
    pv[i] = e2.dot(mesh.vertices[i]);
    u0 = std::min(u0, pu[i]);
    u1 = std::max(u1, pu[i]);
    v0 = std::min(v0, pv[i]);
    v1 = std::max(v1, pv[i]);
  }
  const double du = (u1 - u0) / resolution;
  const double dv = (v1 - v0) / resolution;
  if (!(du > 0.0) || !(dv > 0.0)) {
    return 0.0;
  }
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(resolution) * resolution, 0);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    // Front faces only: every line of sight through a closed solid leaves it through one.
    if (!(mesh.doubleAreaNormal(t).dot(d) > 0.0)) {
      continue;
    }
    const auto& f = mesh.triangles[t];
    // Pixel coordinates: pixel (i, j) has its centre at (i + 1/2, j + 1/2).
    const double ax = (pu[f[0]] - u0) / du, ay = (pv[f[0]] - v0) / dv;
    const double bx = (pu[f[1]] - u0) / du, by = (pv[f[1]] - v0) / dv;
    const double cx = (pu[f[2]] - u0) / du, cy = (pv[f[2]] - v0) / dv;
    const double area2 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area2 == 0.0) {
      continue;
    }
    const double sign = area2 > 0.0 ? 1.0 : -1.0;
    const int i0 = std::max(0, static_cast<int>(std::ceil(std::min({ax, bx, cx}) - 0.5)));
    const int i1 = std::min(resolution - 1, static_cast<int>(std::floor(std::max({ax, bx, cx}) - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil(std::min({ay, by, cy}) - 0.5)));
    const int j1 = std::min(resolution - 1, static_cast<int>(std::floor(std::max({ay, by, cy}) - 0.5)));
    for (int j = j0; j <= j1; ++j) {
      const double py = j + 0.5;
      for (int i = i0; i <= i1; ++i) {
        const double px = i + 0.5;
        // Edge functions, inclusive: a centre on an edge shared by two triangles is covered (no cracks).
        const double w0 = sign * ((bx - ax) * (py - ay) - (by - ay) * (px - ax));
        const double w1 = sign * ((cx - bx) * (py - by) - (cy - by) * (px - bx));
        const double w2 = sign * ((ax - cx) * (py - cy) - (ay - cy) * (px - cx));
        if (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) {
          covered[static_cast<std::size_t>(j) * resolution + i] = 1;
        }
      }
    }
  }
  std::size_t count = 0;
  for (const auto c : covered) {
    count += c;
  }
  return static_cast<double>(count) * du * dv;
}

bool isConvex(const geometry::TriangleMesh& mesh, double relativeTolerance) {
  const double size = mesh.bounds().size().norm();
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Vec3 n = mesh.doubleAreaNormal(t);
    const double length = n.norm();
    if (!(length > 0.0)) {
      continue;
    }
    const Vec3 unit = n / length;
    const double offset = unit.dot(mesh.vertices[mesh.triangles[t][0]]);
    for (const Vec3& v : mesh.vertices) {
      if (unit.dot(v) - offset > relativeTolerance * size) {
        return false;
      }
    }
  }
  return true;
}

ProjectedAreaTable::ProjectedAreaTable(const geometry::TriangleMesh& mesh, const ProjectedAreaSettings& settings)
    : n_(settings.nodesPerEdge) {
  if (n_ < 3 || n_ % 2 == 0 || n_ > 129) {
    core::failInput("projected area table",
                    "nodesPerEdge = {}: must be odd and between 3 and 129 (9 gives 386 directions)", n_);
  }
  if (settings.rasterResolution < 16 || settings.rasterResolution > 8192) {
    core::failInput("projected area table", "rasterResolution = {}: must be between 16 and 8192 pixels",
                    settings.rasterResolution);
  }
  convex_ = isConvex(mesh);
  using Method = ProjectedAreaSettings::Method;
  exact_ = settings.method == Method::Exact || (settings.method == Method::Automatic && convex_);
  if (exact_ && mesh.triangleCount() <= kDirectTriangles) {
    areaNormals_.reserve(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      areaNormals_.push_back(mesh.doubleAreaNormal(t));
    }
    return;
  }
  const int m = (n_ - 1) / 2;
  const int perFace = n_ * n_;
  values_.assign(static_cast<std::size_t>(3 * perFace), 0.0);
  // Each node writes its own slot: the table is the same for any thread count.
#pragma omp parallel for schedule(dynamic, 1)
  for (int node = 0; node < 3 * perFace; ++node) {
    const int a = node / perFace;
    const int j = (node % perFace) / n_;
    const int i = node % n_;
    const auto [b, c] = otherAxes(a);
    Vec3 d;
    d[a] = 1.0;
    d[b] = nodeTangent(i - m, m);
    d[c] = nodeTangent(j - m, m);
    const Vec3 unit = canonical(d).normalized();
    values_[static_cast<std::size_t>(node)] =
        exact_ ? convexProjectedArea(mesh, unit) : rasterisedProjectedArea(mesh, unit, settings.rasterResolution);
  }
}

double ProjectedAreaTable::operator()(const Vec3& direction) const {
  if (!areaNormals_.empty()) {
    const double length = direction.norm();
    if (!(length > 0.0)) {
      return 0.0;
    }
    double sum = 0.0;
    for (const Vec3& n : areaNormals_) {
      sum += std::abs(n.dot(direction));
    }
    return 0.25 * sum / length;
  }
  if (values_.empty()) {
    return 0.0;
  }
  int a = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(direction[k]) > std::abs(direction[a])) {
      a = k;
    }
  }
  const double da = std::abs(direction[a]);
  if (!(da > 0.0)) {
    return 0.0;
  }
  // On the face the direction points through (its mirror image for the -a face, A(d) = A(-d)).
  const double flip = direction[a] > 0.0 ? 1.0 : -1.0;
  const auto [b, c] = otherAxes(a);
  const double scale = 4.0 / std::numbers::pi;
  const double xi = scale * std::atan(flip * direction[b] / da);
  const double eta = scale * std::atan(flip * direction[c] / da);
  const double last = n_ - 1;
  const double gx = std::clamp(0.5 * (xi + 1.0) * last, 0.0, last);
  const double gy = std::clamp(0.5 * (eta + 1.0) * last, 0.0, last);
  const int i = std::min(static_cast<int>(gx), n_ - 2);
  const int j = std::min(static_cast<int>(gy), n_ - 2);
  const double fx = gx - i, fy = gy - j;
  const double* v = values_.data() + static_cast<std::size_t>(a) * n_ * n_;
  const auto at = [&](int ii, int jj) { return v[static_cast<std::size_t>(jj) * n_ + ii]; };
  return (1.0 - fy) * ((1.0 - fx) * at(i, j) + fx * at(i + 1, j)) +
         fy * ((1.0 - fx) * at(i, j + 1) + fx * at(i + 1, j + 1));
}

std::size_t ProjectedAreaTable::directions() const {
  return n_ > 0 ? static_cast<std::size_t>(6) * (n_ - 1) * (n_ - 1) + 2 : 0;
}

} // namespace armour::hydro
