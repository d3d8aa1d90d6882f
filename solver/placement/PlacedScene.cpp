// SPDX-License-Identifier: GPL-3.0-or-later
#include "placement/PlacedScene.hpp"

#include "simulation/CheckpointFile.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "core/JsonWriter.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

namespace armour::placement {
namespace {

using core::jsonString;

/// Shortest text that reads back to the same double.
std::string num(double v) { return fmt::format("{}", v); }

YAML::Node flowList(std::initializer_list<double> values) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (double v : values) list.push_back(num(v));
  list.SetStyle(YAML::EmitterStyle::Flow);
  return list;
}

std::string jsonList(const std::vector<std::string>& names) {
  std::string out = "[";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + jsonString(names[i]);
  return out + "]";
}

} // namespace

std::string placedSceneYaml(const std::string& inputYaml, const PlacementResult& result,
                            const std::string& initialState) {
  YAML::Node root = YAML::Load(inputYaml);
  root.remove("placement");
  if (!initialState.empty()) root["initial_state"] = initialState;
  // The placed scene's own run output goes beside it under its own name.
  if (root["output"] && root["output"].IsMap()) root["output"].remove("folder");
  const io::Scene& scene = result.scene;
  if (!result.addedShapes.empty()) {
    if (!root["shapes"] || !root["shapes"].IsMap()) root["shapes"] = YAML::Node(YAML::NodeType::Map);
    for (const io::ShapeSpec& s : result.addedShapes) {
      YAML::Node shape;
      shape["generator"] = s.generator;
      shape["seed"] = s.seed;
      root["shapes"][s.name] = shape;
    }
  }
  if (!root["bodies"] || !root["bodies"].IsSequence()) root["bodies"] = YAML::Node(YAML::NodeType::Sequence);
  for (std::size_t i = result.firstAddedBody; i < scene.bodies.size(); ++i) {
    const io::Body& b = scene.bodies[i];
    YAML::Node body;
    body["name"] = b.name;
    body["shape"] = scene.shapes[b.shape].name;
    body["volume"] = num(*b.volume);
    body["material"] = scene.materials[b.material].name;
    body["position"] = flowList({b.position.x(), b.position.y(), b.position.z()});
    YAML::Node orientation;
    orientation["quaternion"] = flowList({b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()});
    orientation.SetStyle(YAML::EmitterStyle::Flow);
    body["orientation"] = orientation;
    if (b.fixed) body["fixed"] = true;
    root["bodies"].push_back(body);
  }
  YAML::Emitter out;
  out << YAML::Comment(fmt::format("Placed by `armour place {}`: {} units, {} rocks. Generated file; edit the "
                                   "placement file and place again instead.",
                                   scene.sourceName, result.summary.units, result.summary.rocks))
      << YAML::Newline << root;
  return std::string(out.c_str()) + "\n";
}

std::string summaryText(const PlacementResult& r) {
  const PlacementSummary& s = r.summary;
  std::string t;
  t += fmt::format("units placed        {} (Dn {:.4g} m){}\n", s.units, s.dn,
                   s.rocks > 0 ? fmt::format(", on {} rocks", s.rocks) : "");
  t += fmt::format("simulated time      {:.2f} s, wall time {:.1f} s\n", s.simulatedTime, s.wallSeconds);
  if (s.gridPackingDensity > 0.0) t += fmt::format("grid packing        {:.4f} (Dn^2 / dx dy)\n", s.gridPackingDensity);
  if (s.windowArea > 0.0) {
    t += fmt::format("packing density     {:.4f} ({} units in the rows' window of {:.1f} m^2)\n", s.packingDensity,
                     s.windowUnits, s.windowArea);
    t += fmt::format("layer thickness     {:.3f} m = {:.3f} Dn\n", s.layerThickness, s.layerThickness / s.dn);
    t += fmt::format("porosity            {:.3f}\n", s.porosity);
  }
  t += fmt::format("largest move        {:.3f} Dn from release (median {:.3f} Dn)\n", s.maxDisplacementDn,
                   s.medianDisplacementDn);
  if (s.medianSettleDriftDn > 0.0 || s.settleCappedUnits > 0 || !s.drifted.empty())
    t += fmt::format("own settles         median drift {:.3f} Dn from first touch, {} units frozen before they rested\n",
                     s.medianSettleDriftDn, s.settleCappedUnits);
  if (!s.drifted.empty())
    t += fmt::format("drifted in settle   {} units: {}\n", s.drifted.size(), fmt::join(s.drifted, ", "));
  if (s.cappedUnits > 0)
    t += fmt::format("crane time cap      {} units released before the pack was at rest\n", s.cappedUnits);
  if (!s.moving.empty())
    t += fmt::format("still moving        {} units: {}\n", s.moving.size(), fmt::join(s.moving, ", "));
  if (!s.moved.empty())
    t += fmt::format("moved > 1 Dn        {} units: {}\n", s.moved.size(), fmt::join(s.moved, ", "));
  return t;
}

std::string summaryJson(const PlacementResult& r) {
  const PlacementSummary& s = r.summary;
  return fmt::format(
      "{{\n  \"scene\": {},\n  \"units\": {},\n  \"rocks\": {},\n  \"dn_m\": {},\n  \"simulated_time_s\": {},\n"
      "  \"wall_time_s\": {},\n  \"grid_packing_density\": {},\n  \"packing_density\": {},\n  \"window_units\": {},\n"
      "  \"window_area_m2\": {},\n  \"layer_thickness_m\": {},\n  \"porosity\": {},\n  \"max_displacement_dn\": {},\n"
      "  \"median_displacement_dn\": {},\n  \"capped_units\": {},\n  \"settle_capped_units\": {},\n"
      "  \"median_settle_drift_dn\": {},\n  \"settle_drifted\": {},\n  \"still_moving\": {},\n"
      "  \"moved_more_than_1dn\": {}\n}}\n",
      jsonString(r.scene.sourceName), s.units, s.rocks, num(s.dn), num(s.simulatedTime), num(s.wallSeconds),
      num(s.gridPackingDensity), num(s.packingDensity), s.windowUnits, num(s.windowArea), num(s.layerThickness),
      num(s.porosity), num(s.maxDisplacementDn), num(s.medianDisplacementDn), s.cappedUnits, s.settleCappedUnits,
      num(s.medianSettleDriftDn), jsonList(s.drifted), jsonList(s.moving), jsonList(s.moved));
}

std::string unitsCsv(const PlacementResult& r) {
  std::string t = "unit,release_x_m,release_y_m,release_z_m,x_m,y_m,z_m,qw,qx,qy,qz,release_time_s,rest_time_s,"
                  "capped,displacement_dn\n";
  const auto& bodies = r.scene.bodies;
  for (std::size_t i = 0; i < r.units.size(); ++i) {
    const UnitRecord& u = r.units[i];
    const io::Body& b = bodies[bodies.size() - r.units.size() + i];
    t += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", u.name, num(u.gridPoint.x()),
                     num(u.gridPoint.y()), num(u.gridPoint.z()), num(b.position.x()), num(b.position.y()),
                     num(b.position.z()), num(b.orientation.w()), num(b.orientation.x()), num(b.orientation.y()),
                     num(b.orientation.z()), num(u.releaseTime), num(u.restTime), u.capped ? 1 : 0,
                     num((b.position - u.gridPoint).norm() / r.summary.dn));
  }
  return t;
}

void writePlacementOutputs(const std::string& inputYaml, const PlacementResult& result,
                           const std::filesystem::path& scenePath, const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) core::failInput(folder.string(), "cannot create the output folder: {}", ec.message());
  // The state first: the scene that names it is written after it.
  const std::filesystem::path statePath = scenePath.parent_path() / (scenePath.stem().string() + "-state.nc");
  simulation::Checkpoint state;
  const simulation::World& world = *result.built.world;
  state.state = world.captureState();
  state.state.time = 0.0;
  state.state.steps = 0;
  for (simulation::BodyId b = 0; b < world.bodies().size(); ++b) state.bodyNames.push_back(world.bodies().info(b).name);
  state.applicationState = io::describeContactModel(result.scene.contact);
  simulation::writeCheckpoint(statePath, state);
  const std::string yaml = placedSceneYaml(inputYaml, result, statePath.filename().string());
  core::writeFileAtomically(scenePath, [&](std::ostream& o) { o << yaml; });
  core::writeFileAtomically(folder / "units.csv", [&](std::ostream& o) { o << unitsCsv(result); });
  core::writeFileAtomically(folder / "placement.json", [&](std::ostream& o) { o << summaryJson(result); });
  core::writeFileAtomically(folder / "placement.txt", [&](std::ostream& o) { o << summaryText(result); });
}

} // namespace armour::placement
