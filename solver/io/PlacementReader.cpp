// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/PlacementReader.hpp"

#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace armour::io::detail {
namespace {

using namespace schema;

// ---------------------------------------------------------------------------------------------
// placement: units to add with `armour place` (docs/placement.md)
// ---------------------------------------------------------------------------------------------

const KeyList kPlacementKeys{"shape", "material", "volume", "dn", "name_prefix", "slope", "method", "grid",
                             "orientation", "crane", "settle", "settle_each", "nest", "lowering", "rocks", "toe_berm", "clearance", "seed", "output"};
const KeyList kPlacementGridKeys{"file", "rows", "units_per_row", "dx", "dy", "packing_density", "first_row", "y_start",
                        "width", "stagger", "jitter", "layers", "layer_shift"};
const KeyList kPlacementOrientationKeys{"mode", "frame", "euler_deg", "max_angle_deg", "tries", "select",
                                        "off_underlayer_cost", "unkeyed_cost", "layer_thickness", "offsets",
                                        "offset_radius", "centroid_weight", "key_reward", "envelope_reward",
                                        "stacked_cost", "drift_cost", "settle_candidates"};
const KeyList kCraneKeys{"speed", "rest_speed", "min_time", "max_time"};
const KeyList kSettleKeys{"rest_speed", "min_time", "max_time"};
const KeyList kSettleEachKeys{"damping", "rest_speed", "rest_time", "max_time", "max_drift", "hold_at_max_drift"};
const KeyList kNestKeys{"moves", "shift", "tilt_deg", "max_drift"};
const KeyList kRockKeys{"count", "dn50", "grading", "shapes", "material", "s_end", "toe_length", "clearance", "tries"};
const KeyList kToeBermKeys{"count", "dn50", "grading", "material", "length", "s_end", "clearance", "tries"};

/// placement.rocks (the underlayer) and placement.toe_berm (heavier rocks in front of the first
/// row, on the underlayer, with its shapes).
void readRocks(const schema::Block& p, const Scene& scene, placement::PlacementSettings& out) {
  using namespace schema;
  const Context& ctx = p.context();
  if (p.has("rocks")) {
    const Block r(ctx, p.get("rocks"), "placement.rocks", kRockKeys);
    placement::RockSettings& rs = out.rocks;
    rs.enabled = true;
    rs.count = static_cast<int>(r.integer("count", 1, "rocks in the underlayer (3436 in seed 000)"));
    rs.dn50 = r.number("dn50", {"m", kPositive, "0.79 (W/10 of a 5 m^3 unit)"});
    rs.grading = r.number("grading", {"-", Range{1.0, 3.0, false, false}, "1.25 (Dn85/Dn15)"}, rs.grading);
    rs.shapes = static_cast<int>(r.integer("shapes", 1, "rock shapes in the library", 12));
    rs.material = r.text("material", "a material name", out.material);
    if (scene.findMaterial(rs.material) < 0) r.failValue("material", "no such material under materials:");
    rs.sEnd = r.number("s_end", {"m", kPositive, "30: rocks up the face to here"}, 0.0);
    rs.toeLength = r.number("toe_length", {"m", kNonNegative, "4: rocks this far offshore along the toe"}, 0.0);
    rs.clearance = r.number("clearance", {"Dn50", kNonNegative, "0.002"}, rs.clearance);
    rs.tries = static_cast<int>(r.integer("tries", 1, "orientations tried per rock", 4));
  }
  if (p.has("toe_berm")) {
    const Block t(ctx, p.get("toe_berm"), "placement.toe_berm", kToeBermKeys);
    if (!out.rocks.enabled)
      t.failValue("count", "a toe berm is laid on the rock underlayer with its rock shapes; add placement.rocks");
    placement::RockSettings& tb = out.toeBerm;
    tb.enabled = true;
    tb.count = static_cast<int>(t.integer("count", 1, "rocks in the berm, e.g. 60"));
    tb.dn50 = t.number("dn50", {"m", kPositive, "1.2: berm rock, heavier than the underlayer's"});
    tb.grading = t.number("grading", {"-", Range{1.0, 3.0, false, false}, "1.25 (Dn85/Dn15)"}, tb.grading);
    tb.material = t.text("material", "a material name", out.rocks.material);
    if (scene.findMaterial(tb.material) < 0) t.failValue("material", "no such material under materials:");
    tb.toeLength = t.number("length", {"m", kPositive, "4: the berm runs this far offshore of the slope's foot"});
    tb.sEnd = t.number("s_end", {"m", kNonNegative, "0: and up the face to here"}, 0.0);
    tb.clearance = t.number("clearance", {"Dn50", kNonNegative, "0.002"}, tb.clearance);
    tb.tries = static_cast<int>(t.integer("tries", 1, "orientations tried per rock", 4));
  }
}

} // namespace

void readPlacement(const schema::Block& top, Scene& scene) {
  using namespace schema;
  if (!top.has("placement")) return;
  const Context& ctx = top.context();
  const Block p(ctx, top.get("placement"), "placement", kPlacementKeys);
  placement::PlacementSettings& out = scene.placement;
  out.enabled = true;
  out.shape = p.text("shape", "the units' shape: a name under shapes: or a generator such as coreloc");
  out.material = p.text("material", "the units' material name");
  if (scene.findMaterial(out.material) < 0) p.failValue("material", "no such material under materials:");
  const int size = p.oneOf({"volume", "dn"}, false, "the units' size");
  out.volume = size == 0 ? p.number("volume", {"m^3", kPositive, "5 (seed 000 Core-Loc)"})
                         : std::pow(p.number("dn", {"m", kPositive, "1.71"}), 3);
  out.namePrefix = p.text("name_prefix", "a name prefix", std::string("unit"));
  out.slope = p.text("slope", "the name of the static slope the grid lies on", std::string());
  out.method = static_cast<placement::Method>(p.choice("method", {"crane", "grid"}, 0));
  out.lowering = static_cast<placement::Lowering>(p.choice("lowering", {"vertical", "slope_normal"}, 0));
  out.seed = p.integer("seed", 0, "seed of orientations, jitter and rocks", scene.seed);
  out.clearance = p.number("clearance", {"Dn", kNonNegative, "0.002: the gap a lowered unit stops at"}, out.clearance);
  out.output = p.text("output", "the placed scene's file name, beside this file", scene.name + "-placed.yaml");

  if (!p.has("grid")) p.failMissing("grid", "where the units go: a grid file or rows, units_per_row, packing_density");
  const Block g(ctx, p.get("grid"), "placement.grid", kPlacementGridKeys);
  placement::GridSettings& gs = out.grid;
  if (g.has("file")) {
    gs.file = std::filesystem::absolute(ctx.baseDir / g.text("file", "a CSV of x,y[,z] (m)")).lexically_normal().string();
    for (std::string_view k : {"rows", "units_per_row", "dx", "dy", "packing_density", "first_row", "stagger",
                               "layers", "layer_shift"})
      g.refuse(k, "a grid file gives the points; remove this key or the file");
  } else {
    gs.rows = static_cast<int>(g.integer("rows", 1, "rows up the slope"));
    // Test presence first: a missing key is a zombie node whose IsScalar() throws YAML::InvalidNode.
    const YAML::Node counts = g.get("units_per_row");
    if (!g.has("units_per_row")) {
      g.failMissing("units_per_row", "units per row: a number or a list repeated cyclically, e.g. [12, 11]");
    } else if (counts.IsScalar()) {
      gs.unitsPerRow = {static_cast<int>(g.integer("units_per_row", 1, "units per row, or a list repeated cyclically"))};
    } else if (counts.IsSequence() && counts.size() > 0) {
      for (auto v : g.integers("units_per_row", counts.size(), 1, "units per row, e.g. [12, 11]"))
        gs.unitsPerRow.push_back(static_cast<int>(v));
    } else {
      g.failMissing("units_per_row", "units per row: a number or a list repeated cyclically, e.g. [12, 11]");
    }
    gs.dx = g.number("dx", {"Dn", kPositive, "2.19 (12 Core-Locs over 45 m)"}, 0.0);
    const int spacing = g.oneOf({"dy", "packing_density"}, false, "the row spacing up the slope");
    if (spacing == 0) gs.dy = g.number("dy", {"Dn", kPositive, "0.73"});
    else gs.packingDensity = g.number("packing_density", {"-", Range{0.0, 2.0, true, false}, "0.625 (seed 000)"});
    gs.firstRow = g.number("first_row", {"Dn", kAnyNumber, "0.5 up the face from its foot"}, gs.firstRow);
    gs.stagger = g.number("stagger", {"-", kUnitInterval, "0.5 alternates; 0.4 for a 60 degree parallelogram"}, gs.stagger);
    gs.layers = static_cast<int>(g.integer("layers", 1, "layers", 1));
    if (g.has("layer_shift")) {
      const auto v = g.numbers("layer_shift", 2, {"Dn", kAnyNumber, "[0.5, 0.5] up the slope and along the trunk"});
      gs.layerShiftS = v[0];
      gs.layerShiftY = v[1];
    }
  }
  gs.yStart = g.number("y_start", {"m", kAnyNumber, "0: the first wall"}, 0.0);
  gs.width = g.number("width", {"m", kPositive, "45 (seed 000)"}, 0.0);
  gs.jitter = g.number("jitter", {"Dn", kNonNegative, "0.05"}, 0.0);

  const Block o(ctx, p.has("orientation") ? p.get("orientation") : YAML::Node(), "placement.orientation",
                kPlacementOrientationKeys);
  placement::OrientationSettings& os = out.orientation;
  os.mode = static_cast<placement::OrientationMode>(o.choice("mode", {"perturbed", "tilted", "random"}, 0));
  os.slopeFrame = o.choice("frame", {"world", "slope"}, 0) == 1;
  if (o.has("euler_deg")) {
    const auto e = o.numbers("euler_deg", 3, {"deg", kAnyNumber, "[0, 0, 0]"});
    os.phiDeg = e[0];
    os.thetaDeg = e[1];
    os.psiDeg = e[2];
  }
  os.maxAngleDeg = o.number("max_angle_deg", {"deg", Range{0.0, 180.0, false, false}, "20 (seed 000)"}, os.maxAngleDeg);
  os.tries = static_cast<int>(o.integer("tries", 1, "orientations tried per unit, the lowest kept", 1));
  os.select = static_cast<placement::OrientationSelect>(o.choice("select", {"lowest", "keyed", "interlocked"}, 0));
  os.offUnderlayerCost = o.number("off_underlayer_cost", {"Dn", kNonNegative, "1"}, os.offUnderlayerCost);
  os.unkeyedCost = o.number("unkeyed_cost", {"Dn", kNonNegative, "0.25"}, os.unkeyedCost);
  os.layerThickness = o.number("layer_thickness", {"Dn", kPositive, "1.52 (Core-Loc, CLI design table)"}, os.layerThickness);
  os.offsets = static_cast<int>(o.integer("offsets", 0, "shifted positions tried per attitude besides the grid point", static_cast<std::uint64_t>(os.offsets)));
  os.offsetRadius = o.number("offset_radius", {"Dn", kNonNegative, "0.35"}, os.offsetRadius);
  os.centroidWeight = o.number("centroid_weight", {"-", kNonNegative, "1"}, os.centroidWeight);
  os.keyReward = o.number("key_reward", {"Dn", kNonNegative, "0.15"}, os.keyReward);
  os.envelopeReward = o.number("envelope_reward", {"Dn", kNonNegative, "1"}, os.envelopeReward);
  os.stackedCost = o.number("stacked_cost", {"Dn", kNonNegative, "2"}, os.stackedCost);
  os.driftCost = o.number("drift_cost", {"-", kNonNegative, "0.25"}, os.driftCost);
  os.settleCandidates = static_cast<int>(o.integer("settle_candidates", 1, "candidates settled alone per unit",
                                                   static_cast<std::uint64_t>(os.settleCandidates)));
  if (os.settleCandidates > 1 && !p.has("settle_each"))
    o.refuse("settle_candidates", "the candidates are settled by settle_each; add settle_each: {} or remove it");
  if (os.select == placement::OrientationSelect::Lowest) {
    o.refuse("layer_thickness", "it is the target of select: keyed or interlocked; add one of them or remove it");
    o.refuse("off_underlayer_cost", "it weighs the candidates of select: keyed or interlocked; add one of them or remove it");
  }
  if (os.select != placement::OrientationSelect::Keyed)
    o.refuse("unkeyed_cost", "it weighs the candidates of select: keyed; add select: keyed or remove it");
  if (os.select != placement::OrientationSelect::Interlocked) {
    for (const char* key : {"offsets", "offset_radius", "centroid_weight", "key_reward", "envelope_reward",
                            "stacked_cost", "drift_cost", "settle_candidates"})
      o.refuse(key, "it belongs to select: interlocked; add select: interlocked or remove it");
  }
  if (os.mode == placement::OrientationMode::Random) {
    o.refuse("euler_deg", "mode: random draws every orientation; remove euler_deg or use mode: perturbed");
    o.refuse("max_angle_deg", "mode: random draws every orientation; remove max_angle_deg or use mode: perturbed");
  }

  const Block c(ctx, p.has("crane") ? p.get("crane") : YAML::Node(), "placement.crane", kCraneKeys);
  placement::CraneSettings& cs = out.crane;
  cs.speed = c.number("speed", {"m/s", kNonNegative, "0.5 (seed 001)"}, cs.speed);
  cs.restSpeed = c.number("rest_speed", {"m/s", kPositive, "0.01"}, cs.restSpeed);
  cs.minTime = c.number("min_time", {"s", kNonNegative, "0.2"}, cs.minTime);
  cs.maxTime = c.number("max_time", {"s", kPositive, "5"}, cs.maxTime);
  if (out.method == placement::Method::Grid && p.has("crane"))
    p.warnValue("crane", "method: grid releases all units together; the crane settings are not used");

  const Block st(ctx, p.has("settle") ? p.get("settle") : YAML::Node(), "placement.settle", kSettleKeys);
  placement::SettleSettings& ss = out.settle;
  ss.restSpeed = st.number("rest_speed", {"m/s", kPositive, "0.005"}, ss.restSpeed);
  ss.minTime = st.number("min_time", {"s", kNonNegative, "0.5"}, ss.minTime);
  ss.maxTime = st.number("max_time", {"s", kPositive, "20"}, ss.maxTime);
  if (ss.minTime > ss.maxTime) st.failValue("min_time", fmt::format("longer than max_time = {} s", ss.maxTime));
  if (cs.minTime > cs.maxTime) c.failValue("min_time", fmt::format("longer than max_time = {} s", cs.maxTime));

  if (p.has("settle_each")) {
    const Block e(ctx, p.get("settle_each"), "placement.settle_each", kSettleEachKeys);
    placement::SettleEachSettings& es = out.settleEach;
    es.enabled = true;
    es.damping = e.number("damping", {"1/s", kNonNegative, "2: velocities decay as exp(-2 t)"}, es.damping);
    es.restSpeed = e.number("rest_speed", {"m/s", kPositive, "0.02"}, es.restSpeed);
    es.restTime = e.number("rest_time", {"s", kNonNegative, "0.1"}, es.restTime);
    es.maxTime = e.number("max_time", {"s", kPositive, "6"}, es.maxTime);
    es.maxDrift = e.number("max_drift", {"Dn", kPositive, "1"}, es.maxDrift);
    es.holdAtMaxDrift = e.flag("hold_at_max_drift", es.holdAtMaxDrift);
    if (es.restTime >= es.maxTime)
      e.failValue("rest_time", fmt::format("not shorter than max_time = {} s: no unit could be found at rest; give a "
                                           "rest_time below max_time (0.1 s of 6 s)", es.maxTime));
  }

  if (p.has("nest")) {
    const Block n(ctx, p.get("nest"), "placement.nest", kNestKeys);
    placement::NestSettings& ns = out.nest;
    ns.enabled = true;
    ns.moves = static_cast<int>(n.integer("moves", 1, "failed random moves in a row that end the slide", 24));
    ns.shift = n.number("shift", {"Dn", kPositive, "0.2"}, ns.shift);
    ns.tiltDeg = n.number("tilt_deg", {"deg", kNonNegative, "10"}, ns.tiltDeg);
    ns.maxDrift = n.number("max_drift", {"Dn", kPositive, "0.75"}, ns.maxDrift);
    if (ns.tiltDeg > 90.0) n.failValue("tilt_deg", "more than 90 deg; a move tilts the unit by at most this angle, give 0 to 90");
  }

  readRocks(p, scene, out);
}

} // namespace armour::io::detail
