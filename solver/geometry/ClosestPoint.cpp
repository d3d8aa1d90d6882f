// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/ClosestPoint.hpp"

namespace armour::geometry {

/// Closest point on triangle (a, b, c) to x, and which Voronoi region of the triangle holds it.
/// The regions are tested in turn with dot products of the edge vectors with x minus a corner
/// (Ericson 2005, Real-Time Collision Detection, section 5.1.5): each test is a sign of a
/// barycentric coordinate of the projection, so no square root and no division until the end.
Vec3 closestPointOnTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, TriangleFeature& feature) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ax = x - a;
  const double d1 = ab.dot(ax);
  const double d2 = ac.dot(ax);
  if (d1 <= 0.0 && d2 <= 0.0) {
    feature = TriangleFeature::Vertex0;
    return a;
  }
  const Vec3 bx = x - b;
  const double d3 = ab.dot(bx);
  const double d4 = ac.dot(bx);
  if (d3 >= 0.0 && d4 <= d3) {
    feature = TriangleFeature::Vertex1;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    feature = TriangleFeature::Edge01;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Vec3 cx = x - c;
  const double d5 = ab.dot(cx);
  const double d6 = ac.dot(cx);
  if (d6 >= 0.0 && d5 <= d6) {
    feature = TriangleFeature::Vertex2;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    feature = TriangleFeature::Edge20;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    feature = TriangleFeature::Edge12;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  feature = TriangleFeature::Face;
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

} // namespace armour::geometry
