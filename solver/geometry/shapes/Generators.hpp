// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file Generators.hpp
/// One factory per shape file in this folder; ShapeLibrary.cpp lists them in its registry.

#include "geometry/ShapeLibrary.hpp"

namespace armour::geometry::shapes {

ShapeGenerator cubeGenerator();
ShapeGenerator antiferGenerator();
ShapeGenerator dolosGenerator();
ShapeGenerator coreLocGenerator();
ShapeGenerator accropodeGenerator();
ShapeGenerator xblocGenerator();
ShapeGenerator tetrapodGenerator();
ShapeGenerator cubipodGenerator();
ShapeGenerator vcrossGenerator();
ShapeGenerator vrcrossGenerator();
ShapeGenerator rockGenerator();
ShapeGenerator voronoiRockGenerator();

} // namespace armour::geometry::shapes
