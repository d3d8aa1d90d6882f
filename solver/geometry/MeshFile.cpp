// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/MeshFile.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ObjFile.hpp"
#include "geometry/StlFile.hpp"
#include "geometry/VtpFile.hpp"

#include <algorithm>
#include <cctype>

namespace armour::geometry {

MeshFormat meshFormatFromName(const std::string& name) {
  if (name == "stl") {
    return MeshFormat::Stl;
  }
  if (name == "stl-ascii") {
    return MeshFormat::StlAscii;
  }
  if (name == "obj") {
    return MeshFormat::Obj;
  }
  if (name == "vtp") {
    return MeshFormat::Vtp;
  }
  core::failInput("--format", "'{}' is not a mesh format; use stl, stl-ascii, obj or vtp", name);
}

MeshFormat meshFormatFromPath(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".stl") {
    return MeshFormat::Stl;
  }
  if (ext == ".obj") {
    return MeshFormat::Obj;
  }
  if (ext == ".vtp") {
    return MeshFormat::Vtp;
  }
  core::failInput(path.string(), "unknown mesh file extension '{}'; use .stl, .obj or .vtp", ext);
}

TriangleMesh readMesh(const std::filesystem::path& path) {
  switch (meshFormatFromPath(path)) {
  case MeshFormat::Stl:
  case MeshFormat::StlAscii: return readStl(path);
  case MeshFormat::Obj: return readObj(path);
  case MeshFormat::Vtp: return readVtp(path);
  }
  return {};
}

void writeMesh(const TriangleMesh& mesh, const std::filesystem::path& path, MeshFormat format) {
  switch (format) {
  case MeshFormat::Stl: writeStl(mesh, path, false); break;
  case MeshFormat::StlAscii: writeStl(mesh, path, true); break;
  case MeshFormat::Obj: writeObj(mesh, path); break;
  case MeshFormat::Vtp: writeVtp(mesh, path); break;
  }
}

TriangleMesh readValidMesh(const std::filesystem::path& path, const std::string& logModule) {
  TriangleMesh mesh = readMesh(path);
  const RepairReport repair = validateMesh(mesh, path.string());
  if (repair.flippedFaces > 0 || repair.inverted) {
    core::logger(logModule)->warn("{}: orientation repaired ({} faces flipped{})", path.string(), repair.flippedFaces,
                                  repair.inverted ? ", mesh turned outward" : "");
  }
  return mesh;
}

} // namespace armour::geometry
