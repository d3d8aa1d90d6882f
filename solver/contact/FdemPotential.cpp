// SPDX-License-Identifier: GPL-3.0-or-later
// FDEM potential contact: faces clipped against sub-tetrahedra (Sutherland-Hodgman), the linear
// potential integrated exactly over the clipped polygons; docs/theory.md, "FDEM potential contact".
#include "contact/FdemPotential.hpp"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace armour::contact {

namespace {

/// A point with data carried along by linear interpolation: position (3) then barycentric
/// coordinates of one or two elements, so the clip planes and potentials stay exact linear
/// functions of the vertex (no re-evaluation after clipping).
template <int D>
using Point = Eigen::Matrix<double, D, 1>;

/// {v : a . v + b >= 0} (the kept side), or a linear function a . v + b.
template <int D>
struct Linear {
  Point<D> a = Point<D>::Zero();
  double b = 0.0;
  [[nodiscard]] double operator()(const Point<D>& v) const { return a.dot(v) + b; }
};

constexpr int kMaxPolygon = 64; ///< a triangle clipped by n planes has at most 3 + n corners
constexpr std::size_t kMaxStaticFaces = kFdemMaxStaticFaces;

template <int D>
struct Polygon {
  std::array<Point<D>, kMaxPolygon> v;
  int n = 0;
};

/// Sutherland-Hodgman against one plane: keeps the part with f >= 0. Returns false, leaving `out`
/// untouched, when the whole polygon is kept (most planes of a sub-tetrahedron do not cut a face).
template <int D>
bool clipPolygon(const Polygon<D>& in, const Linear<D>& f, Polygon<D>& out) {
  std::array<double, kMaxPolygon> value;
  bool anyOut = false, anyIn = false;
  for (int i = 0; i < in.n; ++i) {
    value[i] = f(in.v[i]);
    (value[i] < 0.0 ? anyOut : anyIn) = true;
  }
  if (!anyOut) return false;
  out.n = 0;
  if (!anyIn) return true;
  const Point<D>* prev = &in.v[in.n - 1];
  double fPrev = value[in.n - 1];
  for (int i = 0; i < in.n; ++i) {
    const Point<D>& cur = in.v[i];
    const double fCur = value[i];
    if (fCur >= 0.0) {
      if (fPrev < 0.0) out.v[out.n++] = *prev + (fPrev / (fPrev - fCur)) * (cur - *prev);
      out.v[out.n++] = cur;
    } else if (fPrev >= 0.0) {
      out.v[out.n++] = *prev + (fPrev / (fPrev - fCur)) * (cur - *prev);
    }
    prev = &cur;
    fPrev = fCur;
  }
  return true;
}

/// Integrals of a linear psi over a planar convex polygon (triangle fan; exact):
/// area, I0 = int psi dA, I1 = int x psi dA, and the largest psi at a corner.
struct Moments {
  double area = 0.0;
  double i0 = 0.0;
  double i2 = 0.0; ///< int psi^2 dA
  Vec3 i1 = Vec3::Zero();
  double maxPsi = 0.0;
  void add(const Moments& o) {
    area += o.area;
    i0 += o.i0;
    i2 += o.i2;
    i1 += o.i1;
    maxPsi = std::max(maxPsi, o.maxPsi);
  }
};

template <int D>
void integratePolygon(const Polygon<D>& p, const Linear<D>& psi, Moments& m) {
  if (p.n < 3) return;
  const Vec3 x0 = p.v[0].template head<3>();
  const double w0 = psi(p.v[0]);
  m.maxPsi = std::max(m.maxPsi, w0);
  for (int i = 1; i + 1 < p.n; ++i) {
    const Vec3 x1 = p.v[i].template head<3>();
    const Vec3 x2 = p.v[i + 1].template head<3>();
    const double w1 = psi(p.v[i]), w2 = psi(p.v[i + 1]);
    m.maxPsi = std::max({m.maxPsi, w1, w2});
    const double area = 0.5 * (x1 - x0).cross(x2 - x0).norm();
    const double sum = w0 + w1 + w2;
    m.area += area;
    m.i0 += area * sum / 3.0;
    m.i2 += area * (w0 * w0 + w1 * w1 + w2 * w2 + w0 * w1 + w1 * w2 + w0 * w2) / 6.0;
    // int x psi over a triangle, both linear: A/12 (sum_i w_i x_i + (sum_i w_i)(sum_i x_i)).
    m.i1 += (area / 12.0) * (w0 * x0 + w1 * x1 + w2 * x2 + sum * (x0 + x1 + x2));
  }
}

/// Clip polygon `p` by all `planes` in turn and integrate psi over what is left.
template <int D>
void clipAndIntegrate(const Polygon<D>& p, std::span<const Linear<D>> planes, const Linear<D>& psi, Moments& m) {
  Polygon<D> buffers[2];
  const Polygon<D>* in = &p;
  int k = 0;
  for (const Linear<D>& plane : planes) {
    if (!clipPolygon(*in, plane, buffers[k])) continue;
    in = &buffers[k];
    k ^= 1;
    if (in->n < 3) return;
  }
  integratePolygon(*in, psi, m);
}

/// The four clip planes of sub-tetrahedron k of an element whose barycentric coordinates sit at
/// entries [offset, offset + 4) of the point: lambda_k >= 0 and lambda_j - lambda_k >= 0.
template <int D>
std::array<Linear<D>, 4> subTetPlanes(int k, int offset) {
  std::array<Linear<D>, 4> planes;
  planes[0].a[offset + k] = 1.0;
  int n = 1;
  for (int j = 0; j < 4; ++j) {
    if (j == k) continue;
    planes[n].a[offset + j] = 1.0;
    planes[n].a[offset + k] = -1.0;
    ++n;
  }
  return planes;
}

/// Contactor faces of element `c` (its mesh `cm`, points mapped into the target frame by
/// R x + t) against target element `t`: moments per face, summed as force and torque in the
/// target's (unscaled) frame: F = -sum n I0, T = -sum I1 x n (about the target origin).
struct Direction {
  Vec3 force = Vec3::Zero();  ///< sum of -n_f I0_f (target frame, unscaled units)
  Vec3 torque = Vec3::Zero(); ///< sum of -I1_f x n_f
  /// sum of I0 x (the direction psi falls fastest, out of the target): the direction the
  /// potential pushes the contactor, whatever the face's tilt
  Vec3 push = Vec3::Zero();
  /// sum of clipped area x max(0, n_f . (direction psi grows)): the area facing the target
  double projectedArea = 0.0;
  Moments m;
};

/// Contactor faces and element boxes of one body mapped into the other's frame, each computed
/// once per pair evaluation, when first needed (an element meets several of the other's).
struct FrameCache {
  std::vector<std::array<Vec3, 3>> corners;
  std::vector<Box3> faceBoxes;
  std::vector<std::uint8_t> faceReady;
  std::vector<Box3> elementBoxes;
  std::vector<std::uint8_t> elementReady;
  explicit FrameCache(const FdemMesh& m)
      : corners(m.faces().size()), faceBoxes(m.faces().size()), faceReady(m.faces().size(), 0),
        elementBoxes(m.elements().size()), elementReady(m.elements().size(), 0) {}
};

void facesInElement(const FdemMesh& cm, const FdemElement& c, const Mat3& R, const Vec3& t, const Mat3& rotation,
                    FrameCache& cache, const FdemElement& target, Direction& out) {
  using P = Point<7>;
  for (std::uint32_t f = c.firstFace; f < c.firstFace + c.faceCount; ++f) {
    const FdemFace& face = cm.faces()[f];
    if (!cache.faceReady[f]) {
      Box3 b;
      for (int i = 0; i < 3; ++i) {
        cache.corners[f][i] = R * face.corners[i] + t;
        b.extend(cache.corners[f][i]);
      }
      cache.faceBoxes[f] = b;
      cache.faceReady[f] = 1;
    }
    const Box3& box = cache.faceBoxes[f];
    if ((box.max.array() < target.box.min.array()).any() || (box.min.array() > target.box.max.array()).any()) {
      continue;
    }
    Polygon<7> tri;
    tri.n = 3;
    for (int i = 0; i < 3; ++i) {
      P& v = tri.v[i];
      const Vec3& x = cache.corners[f][i];
      v.head<3>() = x;
      for (int k = 0; k < 4; ++k) v[3 + k] = target.lambda(k, x);
    }
    bool outside = false;
    for (int k = 0; k < 4 && !outside; ++k) {
      outside = tri.v[0][3 + k] < 0.0 && tri.v[1][3 + k] < 0.0 && tri.v[2][3 + k] < 0.0;
    }
    if (outside) continue;
    Moments m;
    for (int k = 0; k < 4; ++k) {
      // Sub-tet k holds the points where lambda_k is the smallest: none of the face if another
      // coordinate is smaller at all three corners.
      bool elsewhere = false;
      for (int j = 0; j < 4 && !elsewhere; ++j) {
        elsewhere = j != k && tri.v[0][3 + j] < tri.v[0][3 + k] && tri.v[1][3 + j] < tri.v[1][3 + k] &&
                    tri.v[2][3 + j] < tri.v[2][3 + k];
      }
      if (elsewhere) continue;
      const auto planes = subTetPlanes<7>(k, 3);
      Linear<7> psi;
      psi.a[3 + k] = 4.0 * target.peak;
      Moments piece;
      clipAndIntegrate<7>(tri, planes, psi, piece);
      if (piece.area <= 0.0) continue;
      const Vec3 inward = target.lambdaGradient[k].normalized(); // psi grows along it
      out.push -= piece.i0 * inward;
      out.projectedArea += piece.area * std::max(0.0, (rotation * face.normal).dot(inward));
      m.add(piece);
    }
    if (m.area <= 0.0) continue;
    const Vec3 n = rotation * face.normal; // the face normal in the target frame (pure rotation)
    out.force -= m.i0 * n;
    out.torque -= m.i1.cross(n);
    out.m.add(m);
  }
}

/// The relative placement of two poses: points of X's unscaled frame into Y's, p_Y = R p_X + t,
/// and the pure rotation between them.
struct Relative {
  Mat3 R, rotation, absR;
  Vec3 t;
  double volumeRatio; ///< (s_X / s_Y)^3
};

Relative relative(const FdemPose& x, const FdemPose& y) {
  Relative r;
  r.rotation = y.rotation.transpose() * x.rotation;
  r.R = r.rotation * (x.scale / y.scale);
  r.t = y.rotation.transpose() * (x.position - y.position) / y.scale;
  r.absR = r.R.cwiseAbs();
  const double q = x.scale / y.scale;
  r.volumeRatio = q * q * q;
  return r;
}

bool overlaps(const Box3& boxX, const Relative& r, const Box3& boxY) {
  const Vec3 c = r.R * boxX.centre() + r.t;
  const Vec3 h = r.absR * (0.5 * boxX.size());
  return !((c + h).array() < boxY.min.array()).any() && !((c - h).array() > boxY.max.array()).any();
}

/// Visit every element pair (c of A, t of B) whose boxes overlap, through both hierarchies, in a
/// fixed order.
template <class Visit>
void forElementPairs(const FdemMesh& a, const Relative& ab, const FdemMesh& b, Visit&& visit,
                     FrameCache* cacheA = nullptr) {
  const auto& na = a.bvh();
  const auto& nb = b.bvh();
  if (na.empty() || nb.empty()) return;
  std::vector<std::pair<std::int32_t, std::int32_t>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [ia, ib] = stack.back();
    stack.pop_back();
    const FdemBvhNode& A = na[ia];
    const FdemBvhNode& B = nb[ib];
    if (!overlaps(A.box, ab, B.box)) continue;
    const bool leafA = A.left < 0, leafB = B.left < 0;
    if (leafA && leafB) {
      for (std::uint32_t i = A.first; i < A.first + A.count; ++i) {
        const std::uint32_t c = a.bvhElements()[i];
        for (std::uint32_t j = B.first; j < B.first + B.count; ++j) {
          const std::uint32_t t = b.bvhElements()[j];
          if (cacheA == nullptr) {
            if (overlaps(a.elements()[c].box, ab, b.elements()[t].box)) visit(c, t);
            continue;
          }
          if (!cacheA->elementReady[c]) {
            const Box3& e = a.elements()[c].box;
            const Vec3 centre = ab.R * e.centre() + ab.t;
            const Vec3 half = ab.absR * (0.5 * e.size());
            cacheA->elementBoxes[c].min = centre - half;
            cacheA->elementBoxes[c].max = centre + half;
            cacheA->elementReady[c] = 1;
          }
          const Box3& bc = cacheA->elementBoxes[c];
          const Box3& bt = b.elements()[t].box;
          if (!((bc.max.array() < bt.min.array()).any() || (bc.min.array() > bt.max.array()).any())) visit(c, t);
        }
      }
      continue;
    }
    const double volA = A.box.size().prod() * ab.volumeRatio, volB = B.box.size().prod();
    if (leafB || (!leafA && volA >= volB)) {
      stack.emplace_back(A.right, ib);
      stack.emplace_back(A.left, ib);
    } else {
      stack.emplace_back(ia, B.right);
      stack.emplace_back(ia, B.left);
    }
  }
}

} // namespace

double fdemBodyPair(const FdemMesh& a, const FdemPose& pa, const FdemMesh& b, const FdemPose& pb, double gradient,
                    std::vector<FdemContact>& out) {
  const Relative ab = relative(pa, pb); // A -> B
  const Relative ba = relative(pb, pa); // B -> A
  const double sA3 = pa.scale * pa.scale * pa.scale, sB3 = pb.scale * pb.scale * pb.scale;
  double maxDepth = 0.0;
  FrameCache cacheA(a), cacheB(b); // A's faces in B's frame, B's faces in A's frame
  forElementPairs(a, ab, b, [&](std::uint32_t ci, std::uint32_t ti) {
    const FdemElement& c = a.elements()[ci];
    const FdemElement& t = b.elements()[ti];
    if (c.faceCount == 0 && t.faceCount == 0) return;
    Direction d1, d2;
    facesInElement(a, c, ab.R, ab.t, ab.rotation, cacheA, t, d1); // A's faces in B's element: B's frame
    facesInElement(b, t, ba.R, ba.t, ba.rotation, cacheB, c, d2); // B's faces in A's element: A's frame
    const double w1 = gradient * sB3 * d1.m.i0, w2 = gradient * sA3 * d2.m.i0;
    maxDepth = std::max({maxDepth, d1.m.maxPsi * pb.scale, d2.m.maxPsi * pa.scale});
    if (!(w1 + w2 > 0.0)) return;
    FdemContact r;
    r.contactor = ci;
    r.target = ti;
    // Direction 1 pushes A: F1 = G sB^3 R_B (-sum n I0); its torque about x_A is
    // (x_B - x_A) x F1 + G sB^4 R_B (-sum I1 x n).
    const Vec3 f1 = gradient * sB3 * (pb.rotation * d1.force);
    const Vec3 t1 = (pb.position - pa.position).cross(f1) + gradient * sB3 * pb.scale * (pb.rotation * d1.torque);
    // Direction 2 pushes B by F2 = G sA^3 R_A (-sum n I0) with torque about x_A G sA^4 R_A (-sum I1 x n);
    // A receives the opposite.
    const Vec3 f2 = -gradient * sA3 * (pa.rotation * d2.force);
    const Vec3 t2 = -gradient * sA3 * pa.scale * (pa.rotation * d2.torque);
    r.force = f1 + f2;
    r.torque = t1 + t2;
    Vec3 point = Vec3::Zero();
    if (w1 > 0.0) point += w1 * (pb.position + pb.rotation * (pb.scale * d1.m.i1 / d1.m.i0));
    if (w2 > 0.0) point += w2 * (pa.position + pa.rotation * (pa.scale * d2.m.i1 / d2.m.i0));
    r.point = point / (w1 + w2);
    const Vec3 push = sB3 * (pb.rotation * d1.push) - sA3 * (pa.rotation * d2.push);
    r.normal = push.norm() > 0.0 ? Vec3(push.normalized()) : Vec3::Zero();
    r.stiffness = gradient * (d1.projectedArea * pb.scale * pb.scale + d2.projectedArea * pa.scale * pa.scale);
    r.depth = r.stiffness > 0.0 ? std::max(0.0, r.force.dot(r.normal)) / r.stiffness : 0.0;
    r.maxDepth = std::max(d1.m.maxPsi * pb.scale, d2.m.maxPsi * pa.scale);
    r.energy = 0.5 * gradient * (d1.m.i2 * sB3 * pb.scale + d2.m.i2 * sA3 * pa.scale);
    out.push_back(r);
  }, &cacheA);
  return maxDepth;
}

double fdemHalfSpaces(const FdemMesh& a, const FdemPose& pa, std::span<const Vec3> normals,
                      std::span<const double> offsets, const Box3& region, double gradient,
                      std::vector<FdemContact>& out) {
  const std::size_t nFaces = normals.size();
  if (nFaces == 0 || nFaces > kMaxStaticFaces || offsets.size() != nFaces) {
    throw std::invalid_argument("fdemHalfSpaces: 1 to 56 faces with one offset each");
  }
  // The clip planes and potential of each cell (the part of the solid nearest to face k).
  std::vector<std::vector<Linear<3>>> cells(nFaces);
  std::vector<Linear<3>> psi(nFaces);
  for (std::size_t k = 0; k < nFaces; ++k) {
    psi[k].a = -normals[k];
    psi[k].b = offsets[k];
    cells[k].push_back(psi[k]); // depth below face k >= 0
    for (std::size_t j = 0; j < nFaces; ++j) {
      if (j == k) continue;
      Linear<3> l; // depth_j - depth_k >= 0
      l.a = normals[k] - normals[j];
      l.b = offsets[j] - offsets[k];
      cells[k].push_back(l);
    }
  }
  const Mat3 R = pa.rotation * pa.scale;
  const Mat3 absR = R.cwiseAbs();
  double maxDepth = 0.0;
  const auto& nodes = a.bvh();
  std::vector<std::int32_t> stack{0};
  while (!stack.empty() && !nodes.empty()) {
    const FdemBvhNode& node = nodes[stack.back()];
    stack.pop_back();
    const Vec3 c = pa.position + R * node.box.centre();
    const Vec3 h = absR * (0.5 * node.box.size());
    if (((c + h).array() < region.min.array()).any() || ((c - h).array() > region.max.array()).any()) continue;
    bool outside = false;
    for (std::size_t k = 0; k < nFaces && !outside; ++k) {
      outside = normals[k].dot(c) - offsets[k] > h.dot(normals[k].cwiseAbs());
    }
    if (outside) continue;
    if (node.left >= 0) {
      stack.push_back(node.right);
      stack.push_back(node.left);
      continue;
    }
    for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
      const FdemElement& e = a.elements()[a.bvhElements()[i]];
      for (std::uint32_t fi = e.firstFace; fi < e.firstFace + e.faceCount; ++fi) {
        const FdemFace& face = a.faces()[fi];
        Polygon<3> tri;
        tri.n = 3;
        for (int v = 0; v < 3; ++v) tri.v[v] = pa.position + R * face.corners[v];
        bool out3 = false;
        for (std::size_t k = 0; k < nFaces && !out3; ++k) {
          out3 = psi[k](tri.v[0]) < 0.0 && psi[k](tri.v[1]) < 0.0 && psi[k](tri.v[2]) < 0.0;
        }
        if (out3) continue;
        Moments m;
        const Vec3 n = pa.rotation * face.normal;
        Vec3 push = Vec3::Zero();
        double projected = 0.0;
        for (std::size_t k = 0; k < nFaces; ++k) {
          Moments piece;
          if (nFaces == 1) {
            clipAndIntegrate<3>(tri, std::span<const Linear<3>>(&psi[0], 1), psi[0], piece);
          } else {
            clipAndIntegrate<3>(tri, cells[k], psi[k], piece);
          }
          if (piece.area <= 0.0) continue;
          push += piece.i0 * normals[k];
          projected += piece.area * std::max(0.0, -n.dot(normals[k]));
          m.add(piece);
        }
        maxDepth = std::max(maxDepth, m.maxPsi);
        if (!(m.i0 > 0.0)) continue;
        FdemContact r;
        r.contactor = fi;
        r.force = -gradient * m.i0 * n;
        r.torque = -gradient * (m.i1 - pa.position * m.i0).cross(n);
        r.point = m.i1 / m.i0;
        r.normal = push.norm() > 0.0 ? Vec3(push.normalized()) : Vec3::Zero();
        r.stiffness = gradient * projected;
        r.depth = r.stiffness > 0.0 ? std::max(0.0, r.force.dot(r.normal)) / r.stiffness : 0.0;
        r.maxDepth = m.maxPsi;
        r.energy = 0.5 * gradient * m.i2;
        out.push_back(r);
      }
    }
  }
  return maxDepth;
}

namespace {

template <int D>
using Tet = std::array<Point<D>, 4>;

template <int D>
Point<D> cut(const Point<D>& p, double fp, const Point<D>& q, double fq) {
  return p + (fp / (fp - fq)) * (q - p);
}

/// Keep the part of each tet with f >= 0, as tets (a cut tet is a tet or a prism of three).
template <int D>
void clipTets(const std::vector<Tet<D>>& in, const Linear<D>& f, std::vector<Tet<D>>& out) {
  out.clear();
  const auto prism = [&](const Point<D>& a, const Point<D>& b, const Point<D>& c, const Point<D>& a2,
                         const Point<D>& b2, const Point<D>& c2) {
    out.push_back({a, b, c, a2});
    out.push_back({b, c, a2, b2});
    out.push_back({c, a2, b2, c2});
  };
  for (const Tet<D>& t : in) {
    std::array<double, 4> v{};
    int inside[4], outside[4], ni = 0, no = 0;
    for (int i = 0; i < 4; ++i) {
      v[i] = f(t[i]);
      if (v[i] >= 0.0) inside[ni++] = i;
      else outside[no++] = i;
    }
    if (ni == 4) {
      out.push_back(t);
    } else if (ni == 1) {
      const int i = inside[0];
      out.push_back({t[i], cut(t[i], v[i], t[outside[0]], v[outside[0]]), cut(t[i], v[i], t[outside[1]], v[outside[1]]),
                     cut(t[i], v[i], t[outside[2]], v[outside[2]])});
    } else if (ni == 3) {
      const int o = outside[0];
      const int a = inside[0], b = inside[1], c = inside[2];
      prism(t[a], t[b], t[c], cut(t[a], v[a], t[o], v[o]), cut(t[b], v[b], t[o], v[o]), cut(t[c], v[c], t[o], v[o]));
    } else if (ni == 2) {
      const int i1 = inside[0], i2 = inside[1], o1 = outside[0], o2 = outside[1];
      prism(t[i1], cut(t[i1], v[i1], t[o1], v[o1]), cut(t[i1], v[i1], t[o2], v[o2]), t[i2],
            cut(t[i2], v[i2], t[o1], v[o1]), cut(t[i2], v[i2], t[o2], v[o2]));
    }
  }
}

/// Volume integral of the linear `psi` over tets (positions in the first 3 entries).
template <int D>
double integrateTets(const std::vector<Tet<D>>& tets, const Linear<D>& psi) {
  double sum = 0.0;
  for (const Tet<D>& t : tets) {
    const Vec3 p0 = t[0].template head<3>();
    const double volume = std::abs((t[1].template head<3>() - p0)
                                       .dot((t[2].template head<3>() - p0).cross(t[3].template head<3>() - p0))) / 6.0;
    sum += volume * 0.25 * (psi(t[0]) + psi(t[1]) + psi(t[2]) + psi(t[3]));
  }
  return sum;
}

template <int D>
double clipAndIntegrateTet(const Tet<D>& tet, std::span<const Linear<D>> planes, const Linear<D>& psi) {
  std::vector<Tet<D>> a{tet}, b;
  for (const Linear<D>& p : planes) {
    clipTets(a, p, b);
    std::swap(a, b);
    if (a.empty()) return 0.0;
  }
  return integrateTets(a, psi);
}

} // namespace

namespace {

/// G^-1 x the energy of X's potential over X n Y: integral over (kept elements of X) n (all
/// tetrahedra of Y) of psi_X, in world units.
double potentialInsideOther(const FdemMesh& x, const FdemPose& px, const FdemMesh& y, const FdemPose& py) {
  const Relative xy = relative(px, py);
  // Barycentric planes and boxes of every tetrahedron of Y (its solid, kept or not).
  struct Solid {
    std::array<Linear<7>, 4> planes;
    Box3 box;
  };
  std::vector<Solid> solids;
  solids.reserve(y.allTets().size());
  for (const auto& tet : y.allTets()) {
    Solid s;
    const Vec3& p0 = y.vertices()[tet[0]];
    Mat3 T;
    for (int j = 0; j < 3; ++j) T.col(j) = y.vertices()[tet[j + 1]] - p0;
    const Mat3 inv = T.inverse();
    Vec3 gSum = Vec3::Zero();
    double cSum = 0.0;
    for (int k = 1; k < 4; ++k) {
      s.planes[k].a.head<3>() = inv.row(k - 1).transpose();
      s.planes[k].b = -inv.row(k - 1).dot(p0);
      gSum += inv.row(k - 1).transpose();
      cSum += s.planes[k].b;
    }
    s.planes[0].a.head<3>() = -gSum;
    s.planes[0].b = 1.0 - cSum;
    for (int j = 0; j < 4; ++j) s.box.extend(y.vertices()[tet[j]]);
    solids.push_back(s);
  }
  double sum = 0.0;
  for (const FdemElement& c : x.elements()) {
    std::array<Point<7>, 5> corner; // nodes 0..3, then the centroid; position in Y's frame, lambda of c
    for (int j = 0; j < 5; ++j) {
      const Vec3 p = j < 4 ? x.vertices()[c.nodes[j]] : c.centroid;
      corner[j].head<3>() = xy.R * p + xy.t;
      for (int k = 0; k < 4; ++k) corner[j][3 + k] = j < 4 ? (k == j ? 1.0 : 0.0) : 0.25;
    }
    for (int i = 0; i < 4; ++i) {
      Tet<7> sub;
      sub[0] = corner[4];
      int n = 1;
      Box3 box;
      box.extend(corner[4].head<3>());
      for (int j = 0; j < 4; ++j) {
        if (j == i) continue;
        sub[n++] = corner[j];
        box.extend(corner[j].head<3>());
      }
      Linear<7> psi;
      psi.a[3 + i] = 4.0 * c.peak * px.scale;
      for (const Solid& s : solids) {
        if ((box.max.array() < s.box.min.array()).any() || (box.min.array() > s.box.max.array()).any()) continue;
        sum += clipAndIntegrateTet<7>(sub, s.planes, psi);
      }
    }
  }
  return sum * py.scale * py.scale * py.scale;
}

} // namespace

double fdemBodyPairEnergy(const FdemMesh& a, const FdemPose& pa, const FdemMesh& b, const FdemPose& pb,
                          double gradient) {
  return gradient * (potentialInsideOther(a, pa, b, pb) + potentialInsideOther(b, pb, a, pa));
}

double fdemHalfSpacesEnergy(const FdemMesh& a, const FdemPose& pa, std::span<const Vec3> normals,
                            std::span<const double> offsets, double gradient) {
  // Over the whole solid of A (every tetrahedron): the static potential does not care which of A's
  // elements carry potential.
  const std::size_t nFaces = normals.size();
  std::vector<std::vector<Linear<3>>> cells(nFaces);
  std::vector<Linear<3>> psi(nFaces);
  for (std::size_t k = 0; k < nFaces; ++k) {
    psi[k].a = -normals[k];
    psi[k].b = offsets[k];
    cells[k].push_back(psi[k]);
    for (std::size_t j = 0; j < nFaces; ++j) {
      if (j == k) continue;
      Linear<3> l;
      l.a = normals[k] - normals[j];
      l.b = offsets[j] - offsets[k];
      cells[k].push_back(l);
    }
  }
  double energy = 0.0;
  const Mat3 R = pa.rotation * pa.scale;
  for (const auto& tet : a.allTets()) {
    Tet<3> t;
    for (int j = 0; j < 4; ++j) t[j] = pa.position + R * a.vertices()[tet[j]];
    for (std::size_t k = 0; k < nFaces; ++k) energy += clipAndIntegrateTet<3>(t, cells[k], psi[k]);
  }
  return gradient * energy;
}

} // namespace armour::contact
