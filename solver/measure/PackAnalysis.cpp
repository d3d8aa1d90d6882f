// SPDX-License-Identifier: GPL-3.0-or-later
#include "measure/PackAnalysis.hpp"

#include "analysis/UnderlayerSurface.hpp"
#include "core/AtomicFile.hpp"
#include "core/CsvText.hpp"
#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "simulation/SceneBuilder.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace armour::measure {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

std::string num(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("NaN"); }
std::string json(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string("null"); }

/// The slope-normal heights (frame coordinates, m) of a body's lowest and highest points: its mesh
/// (principal frame at scale 1) scaled and placed at the body's pose.
Eigen::Vector2d extentOf(const simulation::World& world, simulation::BodyId b, const analysis::SlopeFrame& frame) {
  geometry::TriangleMesh mesh = world.shape(world.bodyShape(b)).mesh;
  for (auto& v : mesh.vertices) v *= world.bodyScale(b);
  return analysis::normalExtent(mesh, world.bodies().position(b), world.bodies().orientation(b), frame);
}

/// The support bodies (every body that is not a unit: the rocks): where they sit, how high, and
/// which are surface stones (analysis/UnderlayerSurface).
analysis::SurfaceStones supportsOf(const io::Scene& scene, const simulation::BuiltScene& built,
                                   const std::vector<std::size_t>& units, const analysis::SlopeFrame& frame) {
  std::vector<bool> isUnit(scene.bodies.size(), false);
  for (std::size_t i : units) isUnit[i] = true;
  const simulation::World& world = *built.world;
  std::vector<analysis::PosedMesh> bodies;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    if (isUnit[i]) continue;
    const auto b = built.bodyIndexOfSceneBody[i];
    bodies.push_back({&world.shape(world.bodyShape(b)).mesh, world.bodyScale(b), world.bodies().position(b),
                      world.bodies().orientation(b)});
  }
  return analysis::surfaceStones(bodies, frame);
}

/// The highest top of the supports whose centroids lie within `radius` of `local` in the slope
/// plane; 0, the frame plane, if none does (unit: m).
double highestTopNear(const analysis::SurfaceStones& supports, const Eigen::Vector3d& local, double radius) {
  double top = 0.0;
  for (std::size_t j = 0; j < supports.top.size(); ++j) {
    if (std::hypot(supports.local[j].x() - local.x(), supports.local[j].y() - local.y()) < radius) {
      top = std::max(top, supports.top[j]);
    }
  }
  return top;
}

} // namespace

PoseMap posesOf(const io::Scene& scene) {
  PoseMap poses;
  for (const io::Body& b : scene.bodies) poses[b.name] = {b.position, b.orientation};
  return poses;
}

PoseMap readPoses(const std::filesystem::path& path) {
  PoseMap poses;
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml") return posesOf(io::readScene(path));
  std::ifstream in(path);
  if (!in) core::failInput(path.string(), "cannot open the state file; give a run's final_state.csv or a scene file");
  std::string line;
  if (!std::getline(in, line)) core::failInput(path.string(), "empty state file");
  const auto header = core::splitCsvLine(line);
  std::map<std::string, std::size_t> col;
  for (std::size_t i = 0; i < header.size(); ++i) col[header[i]] = i;
  for (const char* key : {"name", "x", "y", "z", "qw", "qx", "qy", "qz"})
    if (!col.count(key))
      core::failInput(path.string(), "column '{}' missing; a state file has the columns of final_state.csv (name, x, y, "
                                     "z, qw, qx, qy, qz)", key);
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (line.empty()) continue;
    const auto f = core::splitCsvLine(line);
    const auto value = [&](const char* key) {
      const std::size_t i = col[key];
      try {
        if (i >= f.size()) throw std::invalid_argument("missing");
        const double v = std::stod(f[i]);
        if (!std::isfinite(v)) throw std::invalid_argument("not finite");
        return v;
      } catch (const std::exception&) {
        core::failInput(fmt::format("{}:{}", path.string(), lineNo), "column {} = '{}': not a finite number", key,
                        i < f.size() ? f[i] : "");
      }
    };
    BodyPose p;
    p.position = {value("x"), value("y"), value("z")};
    p.orientation = Eigen::Quaterniond(value("qw"), value("qx"), value("qy"), value("qz")).normalized();
    std::string name = f[col["name"]];
    poses[name] = p;
  }
  return poses;
}

namespace {

/// The slope frame of a pack: the face of the scene's (first) slope, or a plane fitted through the
/// units (a level plane when they have no spread along x to fit).
void setPackFrame(PackReport& r, const io::Scene& scene, const std::vector<Eigen::Vector3d>& positions) {
  if (!scene.statics.slopes.empty()) {
    const io::StaticSlope& s = scene.statics.slopes.front();
    r.frame = analysis::SlopeFrame::fromTanAlpha(s.tanAlpha, Eigen::Vector3d(s.origin.x(), 0.0, s.origin.y()));
    r.frameFromSlope = true;
  } else {
    try {
      r.frame = analysis::fitSlopeFrame(positions);
    } catch (const core::InputError&) {
      // No spread along x to fit a gradient to (a tower, a single column): a level plane.
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& p : positions) mean += p / static_cast<double>(positions.size());
      r.frame = analysis::SlopeFrame::fromTanAlpha(0.0, mean);
    }
  }
}

/// The layer on the slope: the underlayer's top, the thickness and the porosity (when the frame is
/// the scene's slope and the units span an area).
void measureLayer(PackReport& r, const std::vector<Eigen::Vector3d>& positions, const std::vector<double>& tops,
                  const std::vector<double>& dn, const analysis::SurfaceStones& supports) {
  if (r.frameFromSlope && r.packingHull.area > 0.0) {
    double s0 = std::numeric_limits<double>::infinity(), s1 = -s0, t0 = s0, t1 = -s0;
    for (const auto& p : positions) {
      const Eigen::Vector3d l = r.frame.toLocal(p);
      s0 = std::min(s0, l.x());
      s1 = std::max(s1, l.x());
      t0 = std::min(t0, l.y());
      t1 = std::max(t1, l.y());
    }
    // The layer's base: the mean top of the support bodies (the rocks) in the window, as
    // armour place measures it (placement.txt), or the slope face where there are none.
    const analysis::SlopeWindow window{s0, s1 + 1e-9, t0, t1 + 1e-9};
    r.underlayerTop = analysis::meanTopIn(supports, window);
    r.underlayerTopAllStones = analysis::meanTopIn(supports, window, false);
    r.surfaceStones = supports.exposedCount;
    r.supportStones = supports.top.size();
    std::vector<double> aboveUnderlayer = tops;
    for (double& t : aboveUnderlayer) t -= r.underlayerTop;
    try {
      r.thickness = analysis::layerThickness(positions, aboveUnderlayer, dn, r.frame, window);
      double volume = 0.0;
      for (double d : dn) volume += d * d * d;
      r.porosity = 1.0 - volume / (r.packingHull.area * r.thickness->thickness);
      if (!(r.porosity >= 0.0 && r.porosity < 1.0)) {
        // The hull runs through the outer centroids, half a unit inside the pack's edge: for a
        // few units it is smaller than their footprint and the formula leaves [0, 1).
        r.porosityNote = fmt::format("1 - N V / (A t) = {:.3g} is no porosity: the hull of the {} centroids "
                                     "({:.3g} m^2) is too small against the units' volume; analyse a pack of "
                                     "more units",
                                     r.porosity, positions.size(), r.packingHull.area);
        r.porosity = std::nan("");
      }
    } catch (const core::InputError&) {
    }
  }
}

/// One row per unit: its place, attitude, contacts, height above the underlayer, displacement.
void addUnitRows(PackReport& r, const io::Scene& scene, const simulation::BuiltScene& built,
                 const std::vector<std::size_t>& units, const std::vector<Eigen::Vector3d>& positions,
                 const std::vector<Eigen::Vector3d>& axes, const std::vector<double>& dn,
                 const std::vector<double>& tops, const std::vector<double>& bottoms,
                 const analysis::SurfaceStones& supports) {
  for (std::size_t k = 0; k < units.size(); ++k) {
    UnitRow row;
    row.name = scene.bodies[units[k]].name;
    row.position = positions[k];
    row.local = r.frame.toLocal(positions[k]);
    row.dn = dn[k];
    row.attitude = analysis::attitude(axes[k], r.frame);
    row.stereo = analysis::stereonetPoint(row.attitude);
    const auto& c = r.contacts.bodies[built.bodyIndexOfSceneBody[units[k]]];
    row.contactNumber = c.contactNumber;
    row.unitNeighbours = c.unitNeighbours;
    row.supportNeighbours = c.supportNeighbours;
    row.maxContactForce = c.maxForce;
    row.heightAboveUnderlayer = (row.local.z() - highestTopNear(supports, row.local, dn[k])) / dn[k];
    row.stacked = c.supportNeighbours == 0 && row.heightAboveUnderlayer > 1.0;
    if (r.thickness) {
      row.topAboveUnderlayer = (tops[k] - r.underlayerTop) / dn[k];
      row.bottomAboveUnderlayer = (bottoms[k] - r.underlayerTop) / dn[k];
    }
    r.touchingUnderlayer += c.supportNeighbours > 0 ? 1 : 0;
    r.stackedUnits += row.stacked ? 1 : 0;
    if (r.displacement) row.displacement = r.displacement->units[k];
    r.units.push_back(row);
  }
}

} // namespace

PackReport analysePack(const io::Scene& input, const AnalyseSettings& settings, const PoseMap* state,
                       const PoseMap* reference) {
  io::Scene declared = input;
  declared.placement = {};
  io::Scene scene = declared;
  if (state != nullptr) {
    for (io::Body& b : scene.bodies) {
      const auto it = state->find(b.name);
      if (it == state->end())
        core::failInput(scene.sourceName, "body '{}' is not in the state file; give the state of a run of this scene",
                        b.name);
      b.position = it->second.position;
      b.orientation = it->second.orientation;
    }
  }
  // Units and supports.
  std::vector<std::size_t> units;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const io::Body& b = scene.bodies[i];
    if (!b.fixed && b.name.rfind(settings.unitPrefix, 0) == 0) units.push_back(i);
  }
  if (units.empty())
    core::failInput(scene.sourceName, "no units to analyse: no movable body{}", settings.unitPrefix.empty()
                                                                                   ? std::string()
                                                                                   : " named " + settings.unitPrefix + "*");
  // The unit axis: all units of one shape (the first unit's).
  const io::ShapeSpec& shape = scene.shapes[scene.bodies[units.front()].shape];
  const std::string generator = shape.source == io::ShapeSource::Generator ? shape.generator : shape.name;
  const Eigen::Vector3d bodyAxis = analysis::unitAxisOf(generator, settings.axis);

  PackReport r;
  r.axis = settings.axis;
  r.rockingAngle = settings.displacement.rockingAngle;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Quaterniond> orientations;
  std::vector<double> dn;
  for (std::size_t i : units) {
    const io::Body& b = scene.bodies[i];
    positions.push_back(b.position);
    orientations.push_back(b.orientation);
  }
  // The World of the scene's own poses (its static domain), its bodies moved to these: sizes and
  // contacts.
  simulation::BuiltScene built = simulation::buildWorld(declared);
  simulation::World& world = *built.world;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const auto b = built.bodyIndexOfSceneBody[i];
    world.bodies().setPosition(b, scene.bodies[i].position);
    // A scene's orientation is the shape's natural frame; the World's body frame is its principal one.
    world.bodies().setOrientation(b, scene.bodies[i].orientation.normalized() * world.bodyNaturalToBody(b).conjugate());
  }
  world.invalidateBoxes();
  for (std::size_t i : units) {
    const auto b = built.bodyIndexOfSceneBody[i];
    dn.push_back(std::cbrt(world.shape(world.bodyShape(b)).unitMass.volume) * world.bodyScale(b));
    if (built.domain.beyondEdge(scene.bodies[i].position)) ++r.unitsOffDomain;
  }
  world.setRecordContacts(true);
  try {
    world.evaluateContacts();
  } catch (const simulation::SimulationError& e) {
    core::failInput(state != nullptr && !settings.stateName.empty() ? settings.stateName : scene.sourceName,
                    "the contacts at these poses cannot be evaluated: {}. The poses put bodies deep inside each "
                    "other or inside the static geometry of {}: give the state of a run of this scene",
                    e.what(), scene.sourceName);
  }
  const std::size_t n = world.bodies().size();
  std::vector<analysis::BodyRole> roles(n + 1, analysis::BodyRole::support); // n: the static geometry
  for (std::size_t i : units) roles[built.bodyIndexOfSceneBody[i]] = analysis::BodyRole::unit;
  std::vector<analysis::Contact> contacts;
  for (const auto& p : world.contactPatches()) {
    const std::size_t other = p.bodyB < 0 ? n : static_cast<std::size_t>(p.bodyB);
    contacts.push_back({p.bodyA, other, p.force.norm()});
  }
  r.contacts = analysis::contactNumbers(contacts, roles);

  setPackFrame(r, scene, positions);
  const auto axes = analysis::noseAxesWorld(orientations, bodyAxis);
  r.p2Q = analysis::p2QTensor(axes);
  try {
    r.p2Mean = analysis::p2MeanDirector(axes);
  } catch (const core::InputError&) {
    r.p2Mean.p2 = std::nan(""); // the axes cancel: no mean direction
  }
  if (units.size() >= 3) {
    try {
      r.packingHull = analysis::packingDensityHull(positions, dn, r.frame);
    } catch (const core::InputError&) {
      // All units in a line: no area.
    }
  }
  std::vector<double> tops, bottoms;
  for (std::size_t i : units) {
    const Eigen::Vector2d e = extentOf(world, built.bodyIndexOfSceneBody[i], r.frame);
    bottoms.push_back(e.x());
    tops.push_back(e.y());
  }
  const analysis::SurfaceStones supports = supportsOf(scene, built, units, r.frame);
  measureLayer(r, positions, tops, dn, supports);
  if (reference != nullptr) {
    std::vector<Eigen::Vector3d> before;
    std::vector<Eigen::Quaterniond> qBefore;
    for (std::size_t i : units) {
      const auto it = reference->find(scene.bodies[i].name);
      if (it == reference->end())
        core::failInput(scene.sourceName, "unit '{}' is not in the reference state", scene.bodies[i].name);
      before.push_back(it->second.position);
      qBefore.push_back(it->second.orientation);
    }
    r.displacement = analysis::measureDisplacement(before, positions, qBefore, orientations, dn, r.frame,
                                                   settings.displacement);
  }
  addUnitRows(r, scene, built, units, positions, axes, dn, tops, bottoms, supports);
  return r;
}

std::string packText(const PackReport& r) {
  std::string t;
  t += fmt::format("units               {}\n", r.units.size());
  t += fmt::format("slope frame         {} (tan alpha {:.4f})\n", r.frameFromSlope ? "the scene's slope" : "fitted to the units",
                   r.frame.tanAlpha());
  t += fmt::format("contacts            coordination number {:.3f}, contact number {:.2f} (min {}, max {}), "
                   "largest pair force {:.4g} N\n",
                   r.contacts.coordinationNumber, r.contacts.meanContactNumber, r.contacts.minContactNumber,
                   r.contacts.maxContactNumber, r.contacts.maxForce);
  t += fmt::format("orientation ({})    P2 {:.4f} (seed 001 eq. 4, mean director), {:.4f} (Q tensor)\n", r.axis,
                   r.p2Mean.p2, r.p2Q.p2);
  if (r.packingHull.area > 0.0)
    t += fmt::format("packing density     {:.4f} over the hull of the centroids ({:.1f} m^2)\n", r.packingHull.phi,
                     r.packingHull.area);
  if (r.thickness)
    t += fmt::format("layer thickness     {:.3f} m (layer coefficient {:.3f}) above the underlayer's top ({:.3f} m "
                     "above the slope face: the mean top of its {} surface stones of {}; of every stone {:.3f} m), "
                     "porosity {}\n",
                     r.thickness->thickness, r.thickness->layerCoefficient, r.underlayerTop, r.surfaceStones,
                     r.supportStones, r.underlayerTopAllStones,
                     r.porosityNote.empty() ? fmt::format("{:.3f}", r.porosity) : "n/a (" + r.porosityNote + ")");
  const double count = static_cast<double>(std::max<std::size_t>(r.units.size(), 1));
  t += fmt::format("underlayer          {} units touch it ({:.3f}); {} stacked ({:.3f}: no support touched, centroid "
                   "> 1 Dn above the underlayer)\n",
                   r.touchingUnderlayer, r.touchingUnderlayer / count, r.stackedUnits, r.stackedUnits / count);
  if (r.unitsOffDomain > 0)
    t += fmt::format("off the model       {} units beyond the static domain: they fell off the edge of the scene's "
                     "unbounded items (a wall closes it)\n",
                     r.unitsOffDomain);
  if (r.displacement) {
    const auto& d = *r.displacement;
    t += fmt::format("displacement        delta_rms {:.4g} m ({:.4g} Dn), horizontal {:.4g} m; mean {:.4g} Dn, max {:.4g} "
                     "Dn; total {:.4g} m\n",
                     d.deltaRms, d.deltaRmsOverDn, d.deltaRmsHorizontal, d.meanDn, d.maxDn, d.total);
    t += fmt::format("middle half (003)   D {:.4g} m, D_z {:.4g} m, D'_z {:.4g} m\n", d.D, d.x.mean, d.x.meanAbsolute);
    for (std::size_t k = 0; k < d.thresholdsDn.size(); ++k)
      t += fmt::format("moved > {:.2g} Dn      {} units\n", d.thresholdsDn[k], d.movedCounts[k]);
    t += fmt::format("rocking             {} units (rotation > {:.3g} deg)\n", d.rockingCount, r.rockingAngle * kDeg);
  }
  return t;
}

void writePackReport(const PackReport& r, const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) core::failInput(folder.string(), "cannot create the output folder: {}", ec.message());
  core::writeFileAtomically(folder / "units.csv", [&](std::ostream& o) {
    o << "unit,x,y,z,s,t,dn,dip_deg,dip_azimuth_deg,stereo_x,stereo_y,contact_number,unit_neighbours,"
         "support_neighbours,max_contact_force_N,height_above_underlayer_dn,stacked,top_above_underlayer_dn,bottom_above_underlayer_dn";
    if (r.displacement) o << ",disp_s,disp_t,disp_n,displacement_dn,rotation_deg,rocking";
    o << "\n";
    for (const UnitRow& u : r.units) {
      o << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", u.name, num(u.position.x()),
                       num(u.position.y()), num(u.position.z()), num(u.local.x()), num(u.local.y()), num(u.dn),
                       num(u.attitude.dip * kDeg), num(u.attitude.dipAzimuth * kDeg), num(u.stereo.x()),
                       num(u.stereo.y()), u.contactNumber, u.unitNeighbours, u.supportNeighbours,
                       num(u.maxContactForce), num(u.heightAboveUnderlayer), u.stacked ? 1 : 0,
                       num(u.topAboveUnderlayer), num(u.bottomAboveUnderlayer));
      if (u.displacement) {
        const auto& d = *u.displacement;
        o << fmt::format(",{},{},{},{},{},{}", num(d.local.x()), num(d.local.y()), num(d.local.z()), num(d.distanceDn),
                         num(d.rotation * kDeg), d.rocking ? 1 : 0);
      }
      o << "\n";
    }
  });
  core::writeFileAtomically(folder / "pack.txt", [&](std::ostream& o) { o << packText(r); });
  core::writeFileAtomically(folder / "pack.json", [&](std::ostream& o) {
    o << "{\n";
    o << fmt::format("  \"units\": {},\n  \"axis\": \"{}\",\n  \"p2_mean_director\": {},\n  \"p2_q_tensor\": {},\n",
                     r.units.size(), r.axis, json(r.p2Mean.p2), json(r.p2Q.p2));
    o << fmt::format("  \"coordination_number\": {},\n  \"mean_contact_number\": {},\n  \"max_contact_force_N\": {},\n",
                     json(r.contacts.coordinationNumber), json(r.contacts.meanContactNumber), json(r.contacts.maxForce));
    o << fmt::format("  \"packing_density_hull\": {},\n  \"hull_area_m2\": {},\n", json(r.packingHull.phi),
                     json(r.packingHull.area));
    o << fmt::format("  \"layer_thickness_m\": {},\n  \"porosity\": {},\n", json(r.thickness ? r.thickness->thickness : NAN),
                     json(r.thickness ? r.porosity : NAN));
    o << fmt::format("  \"underlayer_mean_top_m\": {},\n  \"underlayer_mean_top_all_stones_m\": {},\n"
                     "  \"underlayer_surface_stones\": {},\n",
                     json(r.underlayerTop), json(r.underlayerTopAllStones), r.surfaceStones);
    o << fmt::format("  \"units_touching_underlayer\": {},\n  \"stacked_units\": {},\n  \"units_off_domain\": {}",
                     r.touchingUnderlayer, r.stackedUnits, r.unitsOffDomain);
    if (r.displacement) {
      const auto& d = *r.displacement;
      std::vector<std::string> counts;
      for (std::size_t k = 0; k < d.thresholdsDn.size(); ++k)
        counts.push_back(fmt::format("\"{}\": {}", d.thresholdsDn[k], d.movedCounts[k]));
      o << fmt::format(",\n  \"delta_rms_m\": {},\n  \"delta_rms_horizontal_m\": {},\n  \"delta_rms_dn\": {},\n"
                       "  \"mean_displacement_dn\": {},\n  \"max_displacement_dn\": {},\n  \"total_displacement_m\": {},\n"
                       "  \"D_m\": {},\n  \"D_z_m\": {},\n  \"D_z_prime_m\": {},\n  \"moved_more_than_dn\": {{{}}},\n"
                       "  \"rocking_units\": {}",
                       json(d.deltaRms), json(d.deltaRmsHorizontal), json(d.deltaRmsOverDn), json(d.meanDn),
                       json(d.maxDn), json(d.total), json(d.D), json(d.x.mean), json(d.x.meanAbsolute),
                       fmt::join(counts, ", "), d.rockingCount);
    }
    o << "\n}\n";
  });
}

} // namespace armour::measure
