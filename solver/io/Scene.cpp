// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/Scene.hpp"

#include "core/Error.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace armour::io {

Vec3 HeightField::alongX() const { return Vec3(1.0, 0.0, tanAlpha).normalized(); }

Vec3 HeightField::corner(int ix, int iy) const {
  return origin + (ix * cellSize) * alongX() + Vec3(0.0, iy * cellSize, 0.0);
}

Vec3 HeightField::lowCentre(int ix, int iy) const {
  const Vec3 centre = origin + ((ix + 0.5) * cellSize) * alongX() + Vec3(0.0, (iy + 0.5) * cellSize, 0.0);
  return centre - Vec3(0.0, 0.0, depth(ix, iy));
}

void generateDepths(HeightField& field) {
  std::mt19937_64 rng(field.seed);
  const auto count = static_cast<std::size_t>(field.cellsX) * static_cast<std::size_t>(field.cellsY);
  field.depths.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    // The top 53 bits give every double in [0, 1) on the 2^-53 lattice with equal weight.
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    field.depths[i] = field.maxDepth * u;
  }
}

std::vector<Vec2> slopeProfile(const StaticSlope& slope) {
  const double x0 = slope.origin.x();
  const double z0 = slope.origin.y();
  std::vector<Vec2> points;
  if (slope.toeHeight > 0.0) {
    points.emplace_back(x0 - slope.toeBaseWidth, z0 - slope.toeHeight);
    points.emplace_back(x0 - slope.toeTopWidth, z0);
  }
  if (points.empty() || points.back().x() < x0) points.emplace_back(x0, z0);
  points.emplace_back(x0 + slope.crestHeight / slope.tanAlpha, z0 + slope.crestHeight);
  return points;
}

double slopeHeight(const StaticSlope& slope, double x) {
  const std::vector<Vec2> p = slopeProfile(slope);
  if (x <= p.front().x()) return p.front().y();
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (x <= p[i].x()) {
      const double run = p[i].x() - p[i - 1].x();
      // A vertical toe face has zero run: x equals both ends, take the upper end (the solid's top).
      if (run <= 0.0) return p[i].y();
      const double t = (x - p[i - 1].x()) / run;
      return p[i - 1].y() + t * (p[i].y() - p[i - 1].y());
    }
  }
  return p.back().y();
}

Vec3 StaticWall::normal() const {
  Vec3 n = Vec3::Zero();
  n[axis] = atMinimum ? 1.0 : -1.0;
  return n;
}

std::ptrdiff_t Scene::findMaterial(const std::string& materialName) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == materialName) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

std::ptrdiff_t Scene::findBody(const std::string& bodyName) const {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == bodyName) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

Quat quaternionFromTaitBryan(double phi, double theta, double psi) {
  // Intrinsic rotations compose to the right: the second turn is about the axis the first one
  // produced, which is the same as turning about the fixed axes in the reverse order.
  Quat q = Eigen::AngleAxisd(phi, Vec3::UnitX()) * Eigen::AngleAxisd(theta, Vec3::UnitY()) *
           Eigen::AngleAxisd(psi, Vec3::UnitZ());
  q.normalize();
  return q;
}

namespace {

std::string vec(const Vec3& v) { return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z()); }

std::string quat(const Quat& q) { return fmt::format("[{}, {}, {}, {}]", q.w(), q.x(), q.y(), q.z()); }

/// The same rotation as x-y'-z'' angles in degrees, theta in [-90, 90] (for reading the log; the
/// quaternion beside it is exact). From R = Rx(phi) Ry(theta) Rz(psi): R02 = sin theta,
/// R12 = -sin phi cos theta, R22 = cos phi cos theta, R01 = -cos theta sin psi, R00 = cos theta cos psi.
std::string eulerDeg(const Quat& q) {
  const Eigen::Matrix3d r = q.toRotationMatrix();
  Vec3 a(std::atan2(-r(1, 2), r(2, 2)), std::asin(std::clamp(r(0, 2), -1.0, 1.0)), std::atan2(-r(0, 1), r(0, 0)));
  // At theta = +-90 degrees only phi +- psi is defined (gimbal lock): report psi = 0 and read phi
  // from R = Rx(phi) Ry(theta), where R21 = sin phi and R11 = cos phi.
  if (std::hypot(r(0, 0), r(0, 1)) < 1e-9) a = Vec3(std::atan2(r(2, 1), r(1, 1)), a.y(), 0.0);
  a *= 180.0 / std::numbers::pi;
  // Round-off residues (-0, 1e-15) say nothing to a reader.
  for (int i = 0; i < 3; ++i)
    if (std::abs(a[i]) < 1e-9) a[i] = 0.0;
  return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", a.x(), a.y(), a.z());
}

std::string heightField(const HeightField& f) {
  double lo = f.maxDepth;
  double hi = 0.0;
  for (double d : f.depths) {
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  if (f.depths.empty()) lo = 0.0;
  return fmt::format("cell_size = {} m, cells = {} x {} (extent {} x {} m along the surface), max_depth = {} m, "
                     "seed = {}, depths drawn in [{:.4g}, {:.4g}] m",
                     f.cellSize, f.cellsX, f.cellsY, f.cellsX * f.cellSize, f.cellsY * f.cellSize, f.maxDepth, f.seed,
                     lo, hi);
}

} // namespace

std::string describeContactModel(const ContactSettings& c) {
  return fmt::format("contact model {}, sample_spacing {} Dn, level_set_cells_per_dn {}, fdem elements_per_unit {}",
                     c.model == ContactModel::Fdem ? "fdem" : "levelset", c.sampleSpacing, c.levelSetCellsPerDn,
                     c.fdemElementsPerUnit);
}

namespace {

/// Appends a line of text and a newline to a description.
struct LineWriter {
  std::string& out;
  void operator()(const std::string& text) const {
    out += text;
    out += '\n';
  }
};

/// The static geometry's lines of describeScene.
void describeStatics(const Scene& s, const LineWriter& line) {
  const auto materialName = [&](std::size_t i) { return i < s.materials.size() ? s.materials[i].name : "?"; };
  line(fmt::format("static ({}):", s.statics.size()));
  for (const StaticPlane& p : s.statics.planes)
    line(fmt::format("  plane {}: point = {} m, normal = {}, material = {}", p.name, vec(p.point), vec(p.normal),
                     materialName(p.material)));
  for (const StaticSlope& sl : s.statics.slopes) {
    line(fmt::format("  slope {}: origin = [{}, {}] m (x, z), tan = {} (angle_deg = {:.6g}, cot = {:.6g}), "
                     "crest_height = {} m, toe_height = {} m, toe_top_width = {} m, toe_base_width = {} m, "
                     "material = {}",
                     sl.name, sl.origin.x(), sl.origin.y(), sl.tanAlpha, std::atan(sl.tanAlpha) * 180.0 / std::numbers::pi,
                     1.0 / sl.tanAlpha, sl.crestHeight, sl.toeHeight, sl.toeTopWidth, sl.toeBaseWidth,
                     materialName(sl.material)));
    if (sl.roughness)
      line(fmt::format("    roughness: {}, y from {} m", heightField(*sl.roughness), sl.roughness->origin.y()));
  }
  for (const StaticHeightField& h : s.statics.heightFields)
    line(fmt::format("  heightfield {}: origin = {} m, tan = {}, {}, material = {}", h.name, vec(h.field.origin),
                     h.field.tanAlpha, heightField(h.field), materialName(h.material)));
  for (const StaticWall& w : s.statics.walls)
    line(fmt::format("  wall {}: axis = {}, position = {} m, side = {} (normal {}), material = {}", w.name,
                     w.axis == 0 ? "x" : "y", w.position, w.atMinimum ? "min" : "max", vec(w.normal()),
                     materialName(w.material)));
  for (const StaticMesh& m : s.statics.meshes)
    line(fmt::format("  mesh {}: file = {}, position = {} m, quaternion = {} (euler_deg = {}), scale = {}, "
                     "material = {}",
                     m.name, m.file.string(), vec(m.position), quat(m.orientation), eulerDeg(m.orientation), m.scale,
                     materialName(m.material)));
}

/// The hydrodynamic loads' lines of describeScene.
void describeHydro(const hydro::HydroSettings& hydroSettings, const LineWriter& line) {
  if (!hydroSettings.enabled) {
    line("hydro: none");
  } else {
    const hydro::HydroSettings& h = hydroSettings;
    line(fmt::format("hydro: bodies = {}", h.bodies));
    switch (h.model) {
    case hydro::HydroModel::Storm: {
      const hydro::StormLoadSettings& st = h.storm;
      line("  model = storm");
      line(fmt::format("  file = {}", st.file));
      line(fmt::format("  offset = [{}, {}] m (the file's x, z of the scene's origin)", st.offsetX, st.offsetZ));
      line(fmt::format("  time_offset = {} s, update_interval = {} s, between_updates = {}, ramp_time = {} s",
                       st.timeOffset, st.updateInterval,
                       st.betweenUpdates == hydro::BetweenUpdates::Hold ? "hold" : "interpolate", st.rampTime));
      line(fmt::format("  wet_alpha = {} (-), element_size = {} Dn, pressure = {}", st.wetAlpha, st.elementSizePerDn,
                       st.pressure));
      // Only when not the default: the checkpoint's scene fingerprint is made from this text, and
      // checkpoints of porous-bed scenes written before the setting existed must still restart.
      if (st.bed.kind == hydro::BedKind::Impermeable) {
        line(fmt::format("  bed = impermeable, bed_level = {} m, bed_tolerance = {} Dn", st.bed.level,
                         st.bed.toleranceDn));
      }
      line(fmt::format("  variability: enabled = {}, seed = {}, patches_per_axis = {}", st.variability.enabled,
                       st.variability.seed, st.variability.patchesPerAxis));
      line(fmt::format("  drag: enabled = {}, coefficient = {} (-)", st.drag.enabled, st.drag.coefficient));
      line(fmt::format("  added_mass: enabled = {}, coefficient = {} (-)", st.addedMass.enabled,
                       st.addedMass.coefficient));
      break;
    }
    case hydro::HydroModel::Oscillating: {
      const hydro::OscillatingForceSettings& o = h.oscillating;
      line("  model = oscillating (seed 001 eq. 1-2)");
      line(fmt::format("  amplitude = {} N, period = {} s, wave_number = {} 1/m, z_min = {} m, z_swl = {} m, "
                       "z_max = {} m, waves = {}{}",
                       o.amplitude, o.period, o.waveNumber, o.zMin, o.zSwl, o.zMax, o.waves,
                       o.waves > 0 ? "" : " (the whole run)"));
      break;
    }
    case hydro::HydroModel::ShallowWave: {
      const hydro::ShallowWaveForceSettings& w = h.shallowWave;
      line("  model = shallow_wave (seed 003 eq. 2)");
      line(fmt::format("  amplitude = {} N, angular_frequency = {} rad/s, slope angle = {} deg, toe_x = {} m, "
                       "depth_at_toe = {} m, ray_spacing = {} m{}, exposure_interval = {} s",
                       w.amplitude, w.angularFrequency, w.slopeAngle * 180.0 / 3.14159265358979323846, w.toeX,
                       w.depthAtToe, w.raySpacing, w.raySpacing > 0 ? "" : " (Dn / 4)", w.exposureInterval));
      break;
    }
    }
  }
}

} // namespace

std::string describeScene(const Scene& s) {
  const auto materialName = [&](std::size_t i) { return i < s.materials.size() ? s.materials[i].name : "?"; };
  std::string out;
  const LineWriter line{out};

  line(fmt::format("scene {} (from {}, paths relative to {})", s.name, s.sourceName, s.baseDir.string()));
  if (!s.description.empty()) line(fmt::format("  description: {}", s.description));
  line(fmt::format("  gravity = {} m/s^2", vec(s.gravity)));
  line(fmt::format("  duration = {} s", s.duration));
  if (s.timeStep.automatic)
    line(fmt::format("  time_step = auto (time_step_safety = {} of the stability limit)", s.timeStep.safety));
  else
    line(fmt::format("  time_step = {} s (fixed; time_step_safety = {} unused)", s.timeStep.value, s.timeStep.safety));
  line(fmt::format("  seed = {}", s.seed));
  if (!s.initialState.empty())
    line(fmt::format("  initial_state = {} (the placement's end state: positions, contacts, friction springs)",
                     s.initialState.string()));

  line("contact:");
  line(fmt::format("  sample_spacing = {} Dn", s.contact.sampleSpacing));
  line(fmt::format("  level_set_cells_per_dn = {} (cells per Dn)", s.contact.levelSetCellsPerDn));
  line(fmt::format("  max_overlap = {} Dn", s.contact.maxOverlap));
  // Printed only when set, as body_damping below: scenes with the explicit dashpot keep their
  // checkpoint fingerprint.
  if (s.contact.dashpot == ContactDashpot::Implicit) line("  dashpot = implicit");

  line("output:");
  line(fmt::format("  folder = {}", s.output.folder.string()));
  line(fmt::format("  vtk_interval = {} s{}", s.output.vtkInterval, s.output.vtkInterval > 0 ? "" : " (off)"));
  line(fmt::format("  series_interval = {} s{}", s.output.seriesInterval, s.output.seriesInterval > 0 ? "" : " (off)"));
  line(fmt::format("  checkpoint_interval = {} s{}", s.output.checkpointInterval,
                   s.output.checkpointInterval > 0 ? "" : " (only at the end)"));
  line(fmt::format("  checkpoint_wall_minutes = {} min{}", s.output.checkpointWallMinutes,
                   s.output.checkpointWallMinutes > 0 ? "" : " (off)"));
  line(fmt::format("  contacts = {}", s.output.contacts));
  if (!s.output.unitLoads.empty())
    line(fmt::format("  unit_loads = [{}] every {} s, clusters of {} Dn", fmt::join(s.output.unitLoads, ", "),
                     s.output.unitLoadsInterval, s.output.unitLoadsCluster));

  line("sleep:");
  line(fmt::format("  enabled = {}", s.sleep.enabled));
  // Printed only when not the default: the description is the scene's fingerprint in checkpoints.
  if (s.sleep.scope != simulation::SleepScope::Island) line("  scope = neighbours");
  line(fmt::format("  linear_speed = {} m/s", s.sleep.linearSpeed));
  line(fmt::format("  angular_speed = {} rad/s", s.sleep.angularSpeed));
  line(fmt::format("  time = {} s", s.sleep.time));
  line(fmt::format("  wake_load_fraction = {}", s.sleep.wakeLoadFraction));
  // Printed only when set: the description is the scene's fingerprint in checkpoints, and scenes
  // without body damping keep the fingerprint they had before the key existed.
  if (s.bodyDamping.linear != 0.0 || s.bodyDamping.angular != 0.0)
    line(fmt::format("body_damping: linear = {} 1/s, angular = {} 1/s", s.bodyDamping.linear, s.bodyDamping.angular));

  line(fmt::format("materials ({}):", s.materials.size()));
  for (const Material& m : s.materials) {
    const std::string dissipation = m.restitution ? fmt::format("restitution = {} (-)", *m.restitution)
                                                  : fmt::format("damping_ratio = {} (-)", m.dampingRatio.value_or(0.0));
    line(fmt::format("  {}: density = {} kg/m^3, friction static = {}, dynamic = {} (-), {}, penalty = {:g} Pa, "
                     "tangential_stiffness_ratio = {} (-)",
                     m.name, m.density, m.frictionStatic, m.frictionDynamic, dissipation, m.penalty,
                     m.tangentialStiffnessRatio));
  }

  line(fmt::format("shapes ({}):", s.shapes.size()));
  for (const ShapeSpec& sh : s.shapes) {
    if (sh.source == ShapeSource::MeshFile) {
      line(fmt::format("  {}: mesh = {}", sh.name, sh.meshFile.string()));
    } else {
      std::vector<std::string> params;
      for (const auto& [key, value] : sh.params) params.push_back(fmt::format("{} = {}", key, value));
      line(fmt::format("  {}: generator = {}, params = {{{}}} (others at their defaults), seed = {}", sh.name,
                       sh.generator, fmt::join(params, ", "), sh.seed));
    }
  }

  line(fmt::format("bodies ({}):", s.bodies.size()));
  for (const Body& b : s.bodies) {
    const std::string shapeName = b.shape < s.shapes.size() ? s.shapes[b.shape].name : "?";
    const std::string size = b.volume
                                 ? fmt::format("volume = {} m^3 (dn = {} m)", *b.volume, std::cbrt(*b.volume))
                                 : fmt::format("scale = {} (the mesh's own size)", b.scale);
    line(fmt::format("  {}: shape = {}, {}, material = {}, position = {} m, quaternion = {} (euler_deg = {}), "
                     "velocity = {} m/s, angular_velocity = {} rad/s, fixed = {}",
                     b.name, shapeName, size, materialName(b.material), vec(b.position), quat(b.orientation),
                     eulerDeg(b.orientation), vec(b.velocity), vec(b.angularVelocity), b.fixed));
  }

  describeStatics(s, line);

  describeHydro(s.hydro, line);

  if (!s.warnings.empty()) {
    line(fmt::format("warnings ({}):", s.warnings.size()));
    for (const std::string& w : s.warnings) line("  " + w);
  }
  return out;
}

UnitLoadSelection selectUnitLoadBodies(const Scene& scene) {
  UnitLoadSelection out;
  std::vector<std::uint8_t> chosen(scene.bodies.size(), 0);
  for (const std::string& entry : scene.output.unitLoads) {
    const bool prefix = !entry.empty() && entry.back() == '*';
    const std::string_view stem = prefix ? std::string_view(entry).substr(0, entry.size() - 1) : std::string_view(entry);
    std::size_t found = 0;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const Body& b = scene.bodies[i];
      if (prefix ? !b.name.starts_with(stem) : b.name != stem) continue;
      if (b.fixed) {
        if (prefix) continue; // a prefix may cover fixed bodies too: they carry no loads of their own
        out.problem = fmt::format("body '{}' is fixed: it never moves, and its loads are not traced; name dynamic "
                                  "bodies", entry);
        return out;
      }
      chosen[i] = 1;
      ++found;
    }
    if (found == 0) {
      out.problem = fmt::format("'{}' names no {}body of the scene; give body names, or a prefix ending in '*' such as "
                                "'unit_*'", entry, prefix ? "dynamic " : "");
      return out;
    }
  }
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (chosen[i] != 0) out.bodies.push_back(i);
  return out;
}

std::vector<std::size_t> unitLoadBodies(const Scene& scene) {
  UnitLoadSelection s = selectUnitLoadBodies(scene);
  if (!s.problem.empty()) core::failInput(scene.sourceName, "output.unit_loads: {}", s.problem);
  return std::move(s.bodies);
}

} // namespace armour::io
