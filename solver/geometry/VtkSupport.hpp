// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file VtkSupport.hpp
/// What every VTK XML writer of ours shares: double-precision points and an atomic, compressed write.

#include "geometry/TriangleMesh.hpp"

#include <vtkSmartPointer.h>

#include <filesystem>
#include <string>
#include <vector>

class vtkPoints;
class vtkXMLWriter;
class vtkDataObject;

namespace armour::geometry {

/// Positions as VTK points in double precision (m).
vtkSmartPointer<vtkPoints> toVtkPoints(const std::vector<Vec3>& positions);

/// While alive, VTK's error and warning messages are collected instead of printed (VTK reports
/// through a global output window, so this is not thread-safe; readers are used from one thread).
class VtkMessageCapture {
public:
  VtkMessageCapture();
  ~VtkMessageCapture();
  VtkMessageCapture(const VtkMessageCapture&) = delete;
  VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;
  /// Everything VTK reported so far, one message per line.
  [[nodiscard]] std::string text() const;

private:
  struct Impl;
  Impl* impl_;
};

/// Write `data` with `writer` (appended binary, zlib) to a temporary sibling, then rename it to `path`.
/// Throws core::InputError naming the path if VTK cannot write.
void writeVtkXmlAtomically(vtkXMLWriter& writer, vtkDataObject* data, const std::filesystem::path& path);

} // namespace armour::geometry
