// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/StlFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace armour::geometry {
namespace {

static_assert(std::endian::native == std::endian::little, "binary STL I/O assumes a little-endian host");

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;

std::string readAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    core::failInput(path.string(), "cannot open the mesh file; check the path");
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

TriangleMesh parseBinary(const std::string& data, const std::filesystem::path& path) {
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  const std::size_t expected = kHeaderBytes + kTriangleBytes * static_cast<std::size_t>(count);
  if (data.size() < expected) {
    core::failInput(path.string(),
                    "binary STL is truncated: the header announces {} triangles ({} bytes) but the file has {} "
                    "bytes; re-export the mesh",
                    count, expected, data.size());
  }
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * count);
  mesh.triangles.reserve(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = data.data() + kHeaderBytes + kTriangleBytes * t + 12; // skip the normal
    float xyz[9];
    std::memcpy(xyz, record, sizeof(xyz));
    const auto base = static_cast<std::int32_t>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      mesh.vertices.emplace_back(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
    }
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

TriangleMesh parseAscii(const std::string& data, const std::filesystem::path& path) {
  TriangleMesh mesh;
  std::istringstream in(data);
  std::string line;
  std::size_t lineNumber = 0;
  int cornersInFacet = 0;
  bool inLoop = false;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) {
      continue;
    }
    if (keyword == "vertex") {
      double x = 0, y = 0, z = 0;
      if (!inLoop || !(words >> x >> y >> z)) {
        core::failInput(fmt::format("{}:{}", path.string(), lineNumber),
                        "bad vertex line '{}': expected 'vertex x y z' inside 'outer loop'", line);
      }
      mesh.vertices.emplace_back(x, y, z);
      ++cornersInFacet;
    } else if (keyword == "outer") {
      inLoop = true;
      cornersInFacet = 0;
    } else if (keyword == "endloop") {
      if (cornersInFacet != 3) {
        core::failInput(fmt::format("{}:{}", path.string(), lineNumber),
                        "facet with {} vertices; STL facets must be triangles", cornersInFacet);
      }
      const auto base = static_cast<std::int32_t>(mesh.vertices.size()) - 3;
      mesh.triangles.push_back({base, base + 1, base + 2});
      inLoop = false;
    } else if (keyword != "solid" && keyword != "facet" && keyword != "endfacet" && keyword != "endsolid") {
      core::failInput(fmt::format("{}:{}", path.string(), lineNumber),
                      "unexpected '{}' in ASCII STL; the file is not STL or is corrupt", keyword);
    }
  }
  if (inLoop) {
    core::failInput(path.string(), "ASCII STL ends inside a facet: the file is truncated; re-export it");
  }
  return mesh;
}

} // namespace

TriangleMesh readStl(const std::filesystem::path& path) {
  const std::string data = readAll(path);
  if (data.size() < kHeaderBytes && data.rfind("solid", 0) != 0) {
    core::failInput(path.string(), "file of {} bytes is too short to be STL", data.size());
  }
  bool binary = true;
  if (data.rfind("solid", 0) == 0) {
    // Many binary exporters also start the header with "solid": decide by the exact size rule.
    std::uint32_t count = 0;
    if (data.size() >= kHeaderBytes) {
      std::memcpy(&count, data.data() + 80, 4);
    }
    binary = data.size() >= kHeaderBytes && data.size() == kHeaderBytes + kTriangleBytes * std::size_t{count};
  }
  TriangleMesh mesh = binary ? parseBinary(data, path) : parseAscii(data, path);
  if (mesh.triangles.empty()) {
    core::failInput(path.string(), "the STL holds no triangles");
  }
  weldVertices(mesh, 0.0);
  return mesh;
}

void writeStl(const TriangleMesh& mesh, const std::filesystem::path& path, bool ascii) {
  core::writeFileAtomically(
      path,
      [&](std::ostream& out) {
        if (ascii) {
          out << "solid armour\n";
          for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const Vec3 n = mesh.doubleAreaNormal(t).normalized();
            out << fmt::format("  facet normal {:.9g} {:.9g} {:.9g}\n    outer loop\n", n.x(), n.y(), n.z());
            for (const auto& p : mesh.corners(t)) {
              out << fmt::format("      vertex {:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
            }
            out << "    endloop\n  endfacet\n";
          }
          out << "endsolid armour\n";
          return;
        }
        char header[80] = {};
        std::snprintf(header, sizeof(header), "binary STL written by armour (units: m)");
        out.write(header, sizeof(header));
        const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
        out.write(reinterpret_cast<const char*>(&count), 4);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
          const Vec3 n = mesh.doubleAreaNormal(t).normalized();
          float record[12];
          for (int k = 0; k < 3; ++k) {
            record[k] = static_cast<float>(n[k]);
          }
          const auto c = mesh.corners(t);
          for (int v = 0; v < 3; ++v) {
            for (int k = 0; k < 3; ++k) {
              record[3 + 3 * v + k] = static_cast<float>(c[v][k]);
            }
          }
          const std::uint16_t attribute = 0;
          out.write(reinterpret_cast<const char*>(record), sizeof(record));
          out.write(reinterpret_cast<const char*>(&attribute), 2);
        }
      },
      !ascii);
}

} // namespace armour::geometry
