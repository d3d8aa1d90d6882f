// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/ObjFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <sstream>

namespace armour::geometry {

TriangleMesh readObj(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) {
    core::failInput(path.string(), "cannot open the mesh file; check the path");
  }
  TriangleMesh mesh;
  std::vector<std::vector<std::int64_t>> faces;
  std::vector<std::size_t> faceLines;
  std::string line;
  std::size_t lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword) || keyword[0] == '#') {
      continue;
    }
    const auto where = [&] { return fmt::format("{}:{}", path.string(), lineNumber); };
    if (keyword == "v") {
      double x = 0, y = 0, z = 0;
      if (!(words >> x >> y >> z)) {
        core::failInput(where(), "bad vertex line '{}': expected 'v x y z'", line);
      }
      mesh.vertices.emplace_back(x, y, z);
    } else if (keyword == "f") {
      std::vector<std::int64_t> corners;
      std::string token;
      while (words >> token) {
        const std::string first = token.substr(0, token.find('/'));
        std::int64_t index = 0;
        const auto [ptr, ec] = std::from_chars(first.data(), first.data() + first.size(), index);
        if (ec != std::errc() || ptr != first.data() + first.size() || index == 0) {
          core::failInput(where(), "bad face index '{}': OBJ indices are non-zero integers", token);
        }
        // Negative indices are relative to the vertices read so far.
        corners.push_back(index > 0 ? index - 1 : static_cast<std::int64_t>(mesh.vertices.size()) + index);
      }
      if (corners.size() < 3) {
        core::failInput(where(), "face with {} corners; a face needs at least 3", corners.size());
      }
      faces.push_back(std::move(corners));
      faceLines.push_back(lineNumber);
    }
  }
  const auto nv = static_cast<std::int64_t>(mesh.vertices.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (auto c : faces[i]) {
      if (c < 0 || c >= nv) {
        core::failInput(fmt::format("{}:{}", path.string(), faceLines[i]),
                        "face refers to vertex {} but the file has {} vertices", c + 1, nv);
      }
    }
    for (std::size_t k = 1; k + 1 < faces[i].size(); ++k) {
      mesh.triangles.push_back({static_cast<std::int32_t>(faces[i][0]), static_cast<std::int32_t>(faces[i][k]),
                                static_cast<std::int32_t>(faces[i][k + 1])});
    }
  }
  if (mesh.triangles.empty()) {
    core::failInput(path.string(), "the OBJ file holds no faces ('f' lines)");
  }
  return mesh;
}

void writeObj(const TriangleMesh& mesh, const std::filesystem::path& path) {
  core::writeFileAtomically(path, [&](std::ostream& out) {
    out << "# written by armour (units: m), counter-clockwise faces seen from outside\n";
    for (const auto& v : mesh.vertices) {
      out << fmt::format("v {:.17g} {:.17g} {:.17g}\n", v.x(), v.y(), v.z());
    }
    for (const auto& f : mesh.triangles) {
      out << fmt::format("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
  });
}

} // namespace armour::geometry
