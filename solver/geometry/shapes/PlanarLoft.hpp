// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file PlanarLoft.hpp
/// Building blocks for polyhedral unit generators: section polygons and lofted OpenCASCADE solids
/// whose faces are exact planes.

#include "geometry/GmshSession.hpp"

#include <vector>

namespace armour::geometry::shapes {

/// Corners of a square `side` wide (m) in the plane through `centre` spanned by the unit vectors
/// e1, e2 (sides along e1 and e2), counter-clockwise about e1 x e2.
std::vector<Vec3> squareSection(const Vec3& centre, const Vec3& e1, const Vec3& e2, double side);

/// Corners of an octagon in the plane through `centre` spanned by the unit vectors e1, e2: a regular
/// octagon `width` across flats (m), flats normal to e1 and e2, then pulled apart by `stretch` (m)
/// on each side along e2 (the two flats normal to e2 move out, the corner cuts keep 45 degrees).
/// Counter-clockwise about e1 x e2.
std::vector<Vec3> octagonSection(const Vec3& centre, const Vec3& e1, const Vec3& e2, double width,
                                 double stretch = 0.0);

/// OCC solid lofted through polygons whose corners correspond in order: two end caps and one
/// quadrilateral per edge between consecutive sections. Callers pass parallel polygons whose
/// corresponding edges are parallel, so every quadrilateral is planar; building the faces as OCC
/// planes (not ruled B-spline patches, as addThruSections would) keeps boolean fusion fast (about
/// 30 times faster here) and the volume exact.
/// @pre a GmshSession is open; at least two sections with the same number of corners.
GmshEntity addPlanarLoft(const std::vector<std::vector<Vec3>>& sections);

} // namespace armour::geometry::shapes
