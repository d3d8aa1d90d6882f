// SPDX-License-Identifier: GPL-3.0-or-later
#include "proxy/CaseChecks.hpp"

#include "core/Error.hpp"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

namespace armour::proxy {

namespace fs = std::filesystem;

namespace {

/// The text of an OpenFOAM dictionary without its // and /* */ comments.
std::string dictionaryText(const fs::path& file) {
  std::ifstream in(file);
  if (!in) core::failInput(file.string(), "cannot read the file; check its permissions");
  std::stringstream s;
  s << in.rdbuf();
  static const std::regex comments(R"(//[^\n]*|/\*[\s\S]*?\*/)");
  return std::regex_replace(s.str(), comments, " ");
}

} // namespace

std::string dynamicMeshType(const fs::path& caseDir) {
  const fs::path file = caseDir / "constant" / "dynamicMeshDict";
  if (!fs::exists(file)) return "staticFvMesh";
  const std::string text = dictionaryText(file);
  static const std::regex entry(R"((^|[\s;{}])dynamicFvMesh\s+([A-Za-z0-9_:]+)\s*;)");
  std::smatch m;
  if (!std::regex_search(text, m, entry)) return "staticFvMesh";
  return m[2].str();
}

void requireStaticMesh(const fs::path& caseDir) {
  const std::string type = dynamicMeshType(caseDir);
  if (type == "staticFvMesh") return;
  core::failInput((caseDir / "constant" / "dynamicMeshDict").string(),
                  "dynamicFvMesh = {}: the mesh changes during the run, and foam-bridge samples static meshes only "
                  "(the unit faces, their voxels and the storm file's samples per voxel are found once; the "
                  "armourSampler function object refuses the run, foam-proxy cannot follow the faces, and the stock "
                  "sets object of the eta band has died with SIGFPE during refinement). Set `dynamicFvMesh "
                  "staticFvMesh;` and refine the free-surface band and the units beforehand (refineMesh, snappyHexMesh "
                  "refinement regions)",
                  type);
}

std::optional<std::array<double, 3>> caseGravity(const fs::path& caseDir) {
  const fs::path file = caseDir / "constant" / "g";
  if (!fs::exists(file)) return std::nullopt;
  const std::string text = dictionaryText(file);
  static const std::regex value(R"((^|[\s;{}])value\s*\(\s*([^\s()]+)\s+([^\s()]+)\s+([^\s()]+)\s*\)\s*;)");
  std::smatch m;
  if (!std::regex_search(text, m, value)) {
    core::failInput(file.string(), "no `value (gx gy gz);` entry: write gravity as e.g. `value (0 0 -9.81);`");
  }
  std::array<double, 3> g{};
  for (int i = 0; i < 3; ++i) {
    try {
      std::size_t used = 0;
      g[static_cast<std::size_t>(i)] = std::stod(m[i + 2].str(), &used);
      if (used != m[i + 2].str().size()) throw std::invalid_argument("trailing characters");
    } catch (const std::exception&) {
      core::failInput(file.string(), "value component {} = '{}' is not a number: write gravity as e.g. "
                                     "`value (0 0 -9.81);`", i, m[i + 2].str());
    }
  }
  return g;
}

void requireGravityAlongMinusZ(const fs::path& caseDir) {
  const auto g = caseGravity(caseDir);
  if (!g) return;
  const double mag = std::sqrt((*g)[0] * (*g)[0] + (*g)[1] * (*g)[1] + (*g)[2] * (*g)[2]);
  if ((*g)[2] < 0.0 && std::abs((*g)[0]) <= 1e-6 * mag && std::abs((*g)[1]) <= 1e-6 * mag) return;
  core::failInput((caseDir / "constant" / "g").string(),
                  "value = ({} {} {}): gravity must point along -z (the storm file has z up, x along the waves and y "
                  "along the trunk). Rotate the case so that z is up and the waves travel along x: transformPoints "
                  "-rotate '(<up axis> (0 0 1))' -rotateFields (e.g. '((0 1 0) (0 0 1))' for a case with y up), then "
                  "set value (0 0 {}) in constant/g",
                  (*g)[0], (*g)[1], (*g)[2], -mag);
}

std::string sourceCasePath(const fs::path& caseDir) {
  fs::path p = fs::absolute(caseDir).lexically_normal();
  if (!p.has_filename() && p != p.root_path()) p = p.parent_path();
  return p.string();
}

} // namespace armour::proxy
