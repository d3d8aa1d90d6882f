// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/ShapeCommands.hpp"

#include "core/Error.hpp"
#include "core/Log.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshFile.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "geometry/SurfaceRefinement.hpp"
#include "geometry/Tetrahedralizer.hpp"
#include "geometry/VtuFile.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

namespace armour::app {
namespace {

using namespace armour::geometry;

struct ExportOptions {
  std::string shape;
  double volume = 0.0;  ///< m^3
  double dn = 0.0;      ///< m
  std::string output;
  std::string format;   ///< "" = from the extension
  std::vector<std::string> params; ///< "name=value"
  std::uint64_t seed = 1;
  double maxEdge = 0.0; ///< m, 0 = no refinement
};

std::map<std::string, double> parseParams(const std::vector<std::string>& items) {
  std::map<std::string, double> out;
  for (const auto& item : items) {
    const auto eq = item.find('=');
    double value = 0.0;
    std::size_t used = 0;
    bool ok = eq != std::string::npos && eq > 0;
    if (ok) {
      try {
        value = std::stod(item.substr(eq + 1), &used);
        ok = used == item.size() - eq - 1;
      } catch (const std::exception&) {
        ok = false;
      }
    }
    if (!ok) {
      core::failInput("--param", "'{}' is not name=value with a number, e.g. --param waist=0.34", item);
    }
    out[item.substr(0, eq)] = value;
  }
  return out;
}

void listShapes(bool markdown) {
  for (const auto& g : shapeGenerators()) {
    if (markdown) {
      std::cout << fmt::format("### `{}`\n\n{}.\n\n- Proportions: {}\n- Source: {}\n", g.name, g.summary,
                               g.proportions, g.source);
      for (const auto& p : g.parameters) {
        std::cout << fmt::format("- `{}` = {} ({}, range {} to {}): {}\n", p.name, p.defaultValue, p.unit, p.min,
                                 p.max, p.description);
      }
      std::cout << "\n";
      continue;
    }
    std::cout << fmt::format("{:<14} {}\n", g.name, g.summary);
    for (const auto& p : g.parameters) {
      std::cout << fmt::format("{:<16}--param {}={} ({}, {}..{}) {}\n", "", p.name, p.defaultValue, p.unit, p.min,
                               p.max, p.description);
    }
  }
}

void exportShape(const ExportOptions& o) {
  if ((o.volume > 0.0) == (o.dn > 0.0)) {
    core::failInput("shape export", "give exactly one of --volume (m^3) or --dn (m, Dn = V^(1/3)); got volume = {}, "
                                    "dn = {}",
                    o.volume, o.dn);
  }
  ShapeRequest request;
  request.volume = o.volume > 0.0 ? o.volume : o.dn * o.dn * o.dn;
  request.params = parseParams(o.params);
  request.seed = o.seed;
  const MeshFormat format = o.format.empty() ? meshFormatFromPath(o.output) : meshFormatFromName(o.format);
  TriangleMesh mesh = makeShape(o.shape, request);
  if (o.maxEdge > 0.0) {
    mesh = refineSurface(mesh, o.maxEdge);
  }
  writeMesh(mesh, o.output, format);
  const MassProperties mp = computeMassProperties(mesh);
  core::logger("armour")->info("wrote {} ({} triangles, V = {:.6g} m^3, Dn = {:.6g} m)", o.output, mesh.triangleCount(),
                               mp.volume, mp.nominalDiameter());
  std::cout << o.output << "\n";
}

void printInfo(const std::string& path, double density) {
  TriangleMesh mesh = readMesh(path);
  const MeshInspection inspection = inspectMesh(mesh);
  const Box3 box = mesh.bounds();
  std::cout << fmt::format("file:          {}\n", path);
  std::cout << fmt::format("vertices:      {}\ntriangles:     {}\n", mesh.vertexCount(), mesh.triangleCount());
  std::cout << fmt::format("bounding box:  [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] x [{:.6g}, {:.6g}] m\n", box.min.x(),
                           box.max.x(), box.min.y(), box.max.y(), box.min.z(), box.max.z());
  std::cout << fmt::format("size:          {:.6g} x {:.6g} x {:.6g} m\n", box.size().x(), box.size().y(), box.size().z());
  std::cout << fmt::format("surface area:  {:.6g} m^2\n", mesh.surfaceArea());
  std::cout << fmt::format("watertight:    {}{}\n", inspection.watertight() ? "yes" : "no",
                           inspection.watertight() ? ""
                                                   : fmt::format(" ({} open, {} non-manifold edges)",
                                                                 inspection.openEdges.size(),
                                                                 inspection.nonManifoldEdges.size()));
  std::string problem;
  try {
    const RepairReport repair = validateMesh(mesh, path);
    if (repair.flippedFaces > 0 || repair.inverted) {
      std::cout << fmt::format("orientation:   repaired ({} faces flipped{})\n", repair.flippedFaces,
                               repair.inverted ? ", mesh inverted to face outward" : "");
    } else {
      std::cout << "orientation:   outward, consistent\n";
    }
  } catch (const MeshError& e) {
    problem = e.what();
  }
  if (!problem.empty()) {
    std::cout << fmt::format("valid solid:   no: {}\n", problem);
    throw core::InputError(problem);
  }
  const MassProperties mp = computeMassProperties(mesh);
  std::cout << "valid solid:   yes\n";
  std::cout << fmt::format("volume:        {:.9g} m^3\n", mp.volume);
  std::cout << fmt::format("Dn:            {:.9g} m\n", mp.nominalDiameter());
  std::cout << fmt::format("centroid:      ({:.9g}, {:.9g}, {:.9g}) m\n", mp.centroid.x(), mp.centroid.y(),
                           mp.centroid.z());
  std::cout << fmt::format("mass:          {:.6g} kg at density {} kg/m^3\n", density * mp.volume, density);
  const Mat3 inertia = mp.inertiaForDensity(density);
  std::cout << "inertia about the centroid (kg m^2), world axes:\n";
  for (int r = 0; r < 3; ++r) {
    std::cout << fmt::format("  [{:14.6e} {:14.6e} {:14.6e}]\n", inertia(r, 0), inertia(r, 1), inertia(r, 2));
  }
  std::cout << "principal moments (kg m^2) and axes:\n";
  for (int k = 0; k < 3; ++k) {
    const auto axis = mp.principalAxes.col(k);
    std::cout << fmt::format("  {:14.6e} along ({:.6f}, {:.6f}, {:.6f})\n", density * mp.principalMoments[k], axis.x(),
                             axis.y(), axis.z());
  }
}

struct MeshToolOptions {
  std::string input;
  std::string output;
  std::string format;     ///< "" = from the extension
  double maxEdge = 0.0;   ///< m
  std::size_t tets = 0;   ///< target tetrahedron count
  bool uniform = false;   ///< refine the surface to the interior size first
};

void refineFile(const MeshToolOptions& o) {
  if (!(o.maxEdge > 0.0)) {
    core::failInput("--max-edge", "{} m: give the largest edge length wanted, a positive size in metres", o.maxEdge);
  }
  const TriangleMesh mesh = refineSurface(readValidMesh(o.input), o.maxEdge);
  writeMesh(mesh, o.output, o.format.empty() ? meshFormatFromPath(o.output) : meshFormatFromName(o.format));
  const SurfaceMeshStats stats = surfaceMeshStats(mesh);
  std::cout << fmt::format("{}: {} triangles, edges {:.4g} to {:.4g} m (mean {:.4g} m), smallest angle {:.3g} deg\n",
                           o.output, stats.triangles, stats.minEdge, stats.maxEdge, stats.meanEdge, stats.minAngleDeg);
}

void tetrahedralizeFile(const MeshToolOptions& o) {
  if ((o.tets > 0) == (o.maxEdge > 0.0)) {
    core::failInput("shape tetra", "give exactly one of --tets (target count) or --max-edge (m); got tets = {}, "
                                   "max-edge = {}",
                    o.tets, o.maxEdge);
  }
  TetrahedralizeOptions options;
  options.targetTetCount = o.tets;
  options.maxEdge = o.maxEdge;
  options.keepSurface = !o.uniform;
  options.source = o.input;
  const TetMesh mesh = tetrahedralize(readValidMesh(o.input), options);
  std::filesystem::path out(o.output);
  if (out.extension() != ".vtu") {
    core::failInput(o.output, "tetrahedral meshes are written as VTK unstructured grids: use the extension .vtu");
  }
  writeVtu(mesh, out);
  const TetMeshQuality q = tetMeshQuality(mesh);
  std::cout << fmt::format("{}: {} tetrahedra, {} vertices, volume {:.9g} m^3\n", o.output, q.tets,
                           mesh.vertices.size(), mesh.totalVolume());
  std::cout << fmt::format("quality: dihedral angles {:.3g} to {:.4g} deg, radius ratio min {:.3g} mean {:.3g}\n",
                           q.minDihedralDeg, q.maxDihedralDeg, q.minRadiusRatio, q.meanRadiusRatio);
}

} // namespace

void addShapeCommands(CLI::App& app, const GlobalOptions& /*global*/) {
  CLI::App* shape = app.add_subcommand("shape", "armour-unit and rock shapes: list, export, inspect, refine, mesh");
  shape->require_subcommand(1);

  auto* list = shape->add_subcommand("list", "list the shape generators and their parameters");
  auto markdown = std::make_shared<bool>(false);
  list->add_flag("--markdown", *markdown, "print the list as Markdown (used for docs/shapes.md)");
  list->callback([markdown] { listShapes(*markdown); });

  auto ex = std::make_shared<ExportOptions>();
  auto* exportCmd = shape->add_subcommand("export", "write a unit of a given size to STL, OBJ or VTP");
  exportCmd->add_option("name", ex->shape, "shape name (see `armour shape list`)")->required();
  exportCmd->add_option("--volume", ex->volume, "unit volume (m^3)");
  exportCmd->add_option("--dn", ex->dn, "nominal diameter Dn = V^(1/3) (m)");
  exportCmd->add_option("-o,--output", ex->output, "output file (.stl, .obj or .vtp)")->required();
  exportCmd->add_option("--format", ex->format, "stl, stl-ascii, obj or vtp (default: from the extension)");
  exportCmd->add_option("--param", ex->params, "generator parameter name=value (repeatable)");
  exportCmd->add_option("--seed", ex->seed, "seed for random shapes (rocks)")->capture_default_str();
  exportCmd->add_option("--max-edge", ex->maxEdge, "refine the surface so no edge is longer than this (m)");
  exportCmd->callback([ex] { exportShape(*ex); });

  auto info = std::make_shared<std::pair<std::string, double>>("", 2400.0);
  auto* infoCmd = shape->add_subcommand("info", "volume, Dn, centroid, inertia, bounding box, watertightness");
  infoCmd->add_option("file", info->first, "mesh file (.stl, .obj, .vtp)")->required();
  infoCmd->add_option("--density", info->second, "density for mass and inertia (kg/m^3)")->capture_default_str();
  infoCmd->callback([info] { printInfo(info->first, info->second); });

  auto rf = std::make_shared<MeshToolOptions>();
  auto* refine = shape->add_subcommand("refine", "split surface edges until none is longer than --max-edge");
  refine->add_option("file", rf->input, "closed mesh (.stl, .obj, .vtp)")->required();
  refine->add_option("--max-edge", rf->maxEdge, "largest edge length (m)")->required();
  refine->add_option("-o,--output", rf->output, "output mesh file")->required();
  refine->add_option("--format", rf->format, "stl, stl-ascii, obj or vtp (default: from the extension)");
  refine->callback([rf] { refineFile(*rf); });

  auto tt = std::make_shared<MeshToolOptions>();
  auto* tetra = shape->add_subcommand("tetra", "tetrahedralise a closed mesh (gmsh) and write a .vtu");
  tetra->add_option("file", tt->input, "closed mesh (.stl, .obj, .vtp)")->required();
  tetra->add_option("--tets", tt->tets, "target number of tetrahedra");
  tetra->add_option("--max-edge", tt->maxEdge, "largest interior edge (m)");
  tetra->add_flag("--uniform", tt->uniform, "refine the surface to the interior size first (about uniform elements)");
  tetra->add_option("-o,--output", tt->output, "output .vtu file")->required();
  tetra->callback([tt] { tetrahedralizeFile(*tt); });
}

} // namespace armour::app
