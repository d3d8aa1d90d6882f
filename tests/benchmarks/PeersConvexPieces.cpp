// SPDX-License-Identifier: GPL-3.0-or-later
#include "benchmarks/PeersConvexPieces.hpp"

#include "geometry/ConvexHull.hpp"
#include "geometry/MassProperties.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace armour::bench {
namespace {

using armour::simulation::Vec3;

ConvexPiece hullPiece(const std::string& name, const std::vector<Vec3>& points) {
  if (points.size() < 4) {
    throw std::runtime_error(fmt::format("convex piece {}: {} vertices, need at least 4", name, points.size()));
  }
  const armour::geometry::ConvexPolyhedron hull = armour::geometry::convexHullPolyhedron(points, name);
  ConvexPiece p;
  p.name = name;
  p.corners = hull.vertices; // the hull's vertices only: Bullet's support mapping walks all of them
  p.normals = hull.normals;
  p.offsets = hull.offsets;
  p.volume = armour::geometry::signedVolume(armour::geometry::triangulateFaces(hull));
  return p;
}

/// Winding number of a closed mesh about x (1 inside, 0 outside): the sum of the triangles'
/// solid angles over 4 pi (Van Oosterom and Strackee 1983).
double windingNumber(const armour::geometry::TriangleMesh& mesh, const Vec3& x) {
  double sum = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - x, b = mesh.vertices[t[1]] - x, c = mesh.vertices[t[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * 3.14159265358979323846);
}

ConvexPieces finish(ConvexPieces out, const armour::simulation::ShapeModel& shape) {
  out.meshVolume = armour::geometry::signedVolume(shape.mesh);
  for (const ConvexPiece& p : out.pieces) {
    out.piecesVolume += p.volume;
  }
  // The union against the mesh, on cell centres of a grid over the box of both.
  Vec3 lo = shape.bounds.min, hi = shape.bounds.max;
  for (const ConvexPiece& p : out.pieces) {
    for (const Vec3& c : p.corners) {
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
  }
  const int n = ConvexPieces::kSamples;
  const Vec3 cell = (hi - lo) / n;
  double outside = 0.0, missed = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Vec3 x = lo + Vec3((i + 0.5) * cell.x(), (j + 0.5) * cell.y(), (k + 0.5) * cell.z());
        const bool inMesh = windingNumber(shape.mesh, x) > 0.5;
        bool inPiece = false;
        for (ConvexPiece& p : out.pieces) {
          bool in = true;
          for (std::size_t f = 0; f < p.normals.size() && in; ++f) {
            in = p.normals[f].dot(x) <= p.offsets[f];
          }
          inPiece = inPiece || in;
          p.outside += in && !inMesh ? 1.0 : 0.0;
        }
        outside += inPiece && !inMesh ? 1.0 : 0.0;
        missed += inMesh && !inPiece ? 1.0 : 0.0;
      }
    }
  }
  const double cellVolume = cell.prod();
  out.outside = outside * cellVolume / out.meshVolume;
  out.missed = missed * cellVolume / out.meshVolume;
  for (ConvexPiece& p : out.pieces) {
    p.outside *= cellVolume / out.meshVolume;
  }
  return out;
}

} // namespace

ConvexPieces wholeHull(const armour::simulation::ShapeModel& shape) {
  ConvexPieces out;
  out.pieces.push_back(hullPiece(shape.name + " hull", shape.mesh.vertices));
  out.how = fmt::format("the convex hull of the mesh ({} corners)", out.pieces.back().corners.size());
  return finish(std::move(out), shape);
}

ConvexPieces coreLocPieces(const armour::simulation::ShapeModel& shape, int pieces) {
  if (pieces != 3 && pieces != 5) {
    throw std::invalid_argument(fmt::format("--pieces {}: choose 3 or 5", pieces));
  }
  const auto& mesh = shape.mesh;
  const armour::simulation::Quat toNatural = shape.naturalToBody.conjugate();
  std::vector<Vec3> natural;
  natural.reserve(mesh.vertices.size());
  double extent = 0.0;
  for (const Vec3& v : mesh.vertices) {
    natural.push_back(toNatural * v);
    extent = std::max(extent, natural.back().cwiseAbs().maxCoeff());
  }
  const double tol = 1e-6 * extent;
  // The outer members' inner faces: planar faces whose normal is +-x, nearest the centre.
  double xInner = extent;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    const Vec3 &a = natural[f[0]], &b = natural[f[1]], &c = natural[f[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    const Vec3 centre = (a + b + c) / 3.0;
    if (std::abs(n.x()) > 1.0 - 1e-9 && n.x() * centre.x() < 0.0) { // faces the centre
      xInner = std::min(xInner, std::abs(centre.x()));
    }
  }
  if (!(xInner < 0.5 * extent)) {
    throw std::runtime_error(fmt::format("{}: no inner faces of outer members found: not a Core-Loc mesh", shape.name));
  }
  // Where the chamfers start: the central member's sections stand at x = 0, +-(x_inner - c) and
  // +-x_inner (CoreLoc.cpp), so x_inner - c is the smallest |x| > 0 of a section corner: the
  // smallest |x| > 0 of a vertex on the member's top or bottom flat (at |y| < |z|; the mesh also
  // has vertices inside the side faces, at other x).
  double xChamfer = xInner;
  for (const Vec3& v : natural) {
    const double x = std::abs(v.x());
    if (x > tol && x < xInner - tol && std::abs(v.y()) < std::abs(v.z())) {
      xChamfer = std::min(xChamfer, x);
    }
  }
  if (!(xChamfer < xInner - tol)) {
    throw std::runtime_error(fmt::format("{}: no chamfer sections found: not a Core-Loc mesh", shape.name));
  }
  // An outer member is a loft of four octagons, at z = +-z_full (the ends of its full-width part)
  // and at its ends, so it is the hull of its corners at |z| >= z_full. Nearer the middle, the
  // central member's sides run on past the inner faces (|x| > x_inner): those vertices are not the
  // outer member's. z_full is the top of the inner faces.
  double zFull = 0.0;
  for (const Vec3& v : natural) {
    if (std::abs(std::abs(v.x()) - xInner) <= tol) {
      zFull = std::max(zFull, std::abs(v.z()));
    }
  }
  std::vector<Vec3> left, right;
  for (std::size_t i = 0; i < natural.size(); ++i) {
    if (std::abs(natural[i].z()) >= zFull - tol) {
      (natural[i].x() < 0.0 ? left : right).push_back(mesh.vertices[i]); // body frame, where Bullet's body lives
    }
  }
  ConvexPiece outerL = hullPiece("outer member x-", left);
  ConvexPiece outerR = hullPiece("outer member x+", right);
  const auto outside = [&](const ConvexPiece& p, const Vec3& v) {
    for (std::size_t f = 0; f < p.normals.size(); ++f) {
      if (p.normals[f].dot(v) > p.offsets[f] + 1e-4 * extent) return true; // clear of the CAD's intersection round-off
    }
    return false;
  };
  // The central member and its chamfers: the vertices between the inner faces (without the
  // inner faces' corners, which are the outer members'), and beyond them those outside both outer
  // members (its sides run on past the inner faces).
  std::vector<Vec3> central, middle, chamferL, chamferR;
  for (std::size_t i = 0; i < natural.size(); ++i) {
    const double x = natural[i].x();
    const Vec3& v = mesh.vertices[i];
    const bool between = std::abs(x) <= xInner + tol && std::abs(natural[i].z()) < zFull - tol;
    if (!between && !(outside(outerL, v) && outside(outerR, v))) {
      continue;
    }
    central.push_back(v);
    if (std::abs(x) <= xChamfer + tol) middle.push_back(v);
    if (x <= -xChamfer + tol) chamferL.push_back(v);
    if (x >= xChamfer - tol) chamferR.push_back(v);
  }
  ConvexPieces out;
  out.pieces.push_back(std::move(outerL));
  out.pieces.push_back(std::move(outerR));
  if (pieces == 3) {
    out.pieces.push_back(hullPiece("central member", central));
    out.how = fmt::format("3 convex hulls of the mesh vertices of each member: the outer members (their corners at "
                          "|z| >= {:.4f} m, |x| >= {:.4f} m) and the central member with its chamfered joins (natural "
                          "frame, m)",
                          zFull, xInner);
  } else {
    out.pieces.push_back(hullPiece("central member", middle));
    out.pieces.push_back(hullPiece("join x-", chamferL));
    out.pieces.push_back(hullPiece("join x+", chamferR));
    out.how = fmt::format("5 convex hulls of the mesh vertices: the outer members (their corners at |z| >= {:.4f} m, "
                          "|x| >= {:.4f} m), the central member between its chamfers (|x| <= {:.4f} m) and each "
                          "chamfered join (|x| >= {:.4f} m) (natural frame, m)",
                          zFull, xInner, xChamfer, xChamfer);
  }
  return finish(std::move(out), shape);
}

} // namespace armour::bench
