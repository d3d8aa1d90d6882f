// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
/// @file HydroFixtures.hpp
/// Fixtures of the hydrodynamic-load tests (test_hydro_pressure, test_hydro_flow): storm files
/// written from analytic fields (still water, a regular oscillation with a variability model), a
/// temporary folder per test (HydroTest), a world of library shapes placed by hand (Scene) and
/// the loads of a StormLoads stage at a given time. Header-only.

#include "hydro/StormLoads.hpp"
#include "simulation/World.hpp"
#include "storm/StormFile.hpp"
#include "support/ShapeCache.hpp"
#include "support/TestMeshes.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

namespace armour::test {

namespace fs = std::filesystem;
using simulation::BodyId;
using simulation::BodySpec;
using simulation::Quat;
using simulation::World;
using simulation::WorldSettings;

inline constexpr double kRho = 1025.0; // kg/m^3, the water of every test file
inline constexpr double kG = 9.81;      // m/s^2

// ------------------------------------------------------------------------------------------------
// Storm files for tests

/// Flow at (t, x, z): what a record stores at a voxel centre.
struct Flow {
  double p = 0.0, u = 0.0, w = 0.0, alpha = 0.0;
};
using FlowField = std::function<Flow(double t, double x, double z)>;
using Elevation = std::function<double(double t, double x)>;

/// A grid of square voxels of side d covering [x0, x1] x [z0, z1] (edges; centres half a voxel in).
inline storm::StormHeader gridHeader(double x0, double x1, double z0, double z1, double d, double swl,
                                     double trunkOrigin = -50.0, double trunkLength = 100.0) {
  storm::StormHeader h;
  for (double x = x0 + 0.5 * d; x < x1; x += d) {
    h.x.push_back(x);
  }
  for (double z = z0 + 0.5 * d; z < z1; z += d) {
    h.z.push_back(z);
  }
  h.samples.assign(h.voxels(), 1);
  h.stillWaterLevel = swl;
  h.waterDensity = kRho;
  h.gravity = kG;
  h.trunkOrigin = trunkOrigin;
  h.trunkLength = trunkLength;
  h.provenance.title = "hydro load tests (HydroFixtures.hpp)";
  h.provenance.sourceCase = "synthetic: test";
  return h;
}

/// Write a storm file with the given records (double precision: the exactness tests need it).
inline void writeStorm(const fs::path& path, const storm::StormHeader& h, const std::vector<double>& times,
                       const FlowField& flow, const Elevation& eta) {
  storm::StormWriteOptions options;
  options.doublePrecision = true;
  storm::StormWriter writer(path.string(), h, options);
  storm::StormRecord r;
  for (const double t : times) {
    r.time = t;
    r.p.assign(h.voxels(), 0.0);
    r.u.assign(h.voxels(), 0.0);
    r.w.assign(h.voxels(), 0.0);
    r.alpha.assign(h.voxels(), 0.0);
    r.eta.assign(h.nx(), 0.0);
    for (std::size_t k = 0; k < h.nz(); ++k) {
      for (std::size_t i = 0; i < h.nx(); ++i) {
        const Flow f = flow(t, h.x[i], h.z[k]);
        const std::size_t v = k * h.nx() + i;
        r.p[v] = f.p;
        r.u[v] = f.u;
        r.w[v] = f.w;
        r.alpha[v] = f.alpha;
      }
    }
    for (std::size_t i = 0; i < h.nx(); ++i) {
      r.eta[i] = eta(t, h.x[i]);
    }
    writer.append(r);
  }
  writer.finish();
}

/// Still water below z = swl: p = rho g (swl - z), alpha = 1 below and 0 above.
inline FlowField hydrostatic(double swl) {
  return [swl](double, double, double z) {
    Flow f;
    if (z < swl) {
      f.p = kRho * kG * (swl - z);
      f.alpha = 1.0;
    }
    return f;
  };
}

inline Elevation flat() {
  return [](double, double) { return 0.0; };
}

/// A temporary folder per test, removed afterwards.
class HydroTest : public ::testing::Test {
protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("armour_hydro_{}_{}", info->name(), ::getpid());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }

  /// Still water with its surface at z = 0 over x in [-10, 10], z in [-12, 2], voxels of 0.5 m:
  /// the surface lies on a voxel boundary, so the interpolated alpha is 1/2 exactly there.
  std::string stillWater(double duration = 100.0) {
    const std::string path = file("still.nc");
    if (!fs::exists(path)) {
      writeStorm(path, gridHeader(-10.0, 10.0, -12.0, 2.0, 0.5, 0.0), {0.0, duration}, hydrostatic(0.0), flat());
    }
    return path;
  }

  fs::path dir_;
};

// ------------------------------------------------------------------------------------------------
// Scenes

inline WorldSettings quietWorld() {
  WorldSettings s;
  s.sleep.enabled = false;
  return s;
}

/// A world with library shapes of 1 m^3 (Dn = 1 m) and bodies placed by hand.
struct Scene {
  World world;
  std::map<std::string, simulation::ShapeId> shapes;
  std::map<double, simulation::MaterialId> materials;

  explicit Scene(const WorldSettings& settings = quietWorld()) : world(settings) {}

  simulation::MaterialId material(double density, double friction = 0.75) {
    auto it = materials.find(density);
    if (it == materials.end()) {
      simulation::Material m;
      m.name = fmt::format("m{}", density);
      m.density = density;
      m.frictionStatic = m.frictionDynamic = friction;
      it = materials.emplace(density, world.addMaterial(m)).first;
    }
    return it->second;
  }
  simulation::ShapeId shape(const std::string& name) {
    auto it = shapes.find(name);
    if (it == shapes.end()) {
      it = shapes.emplace(name, world.addShape(name, test::unitShape(name))).first;
    }
    return it->second;
  }
  BodyId add(const std::string& shapeName, const Vec3& position, const Quat& orientation = Quat::Identity(),
             double scale = 1.0, double density = 2400.0, const std::string& name = "unit") {
    BodySpec b;
    b.name = name;
    b.shape = shape(shapeName);
    b.scale = scale;
    b.material = material(density);
    b.position = position;
    b.orientation = orientation;
    return world.addBody(b);
  }
};

inline hydro::StormLoadSettings settingsFor(const std::string& path) {
  hydro::StormLoadSettings s;
  s.file = path;
  s.variability.enabled = false;
  return s;
}

/// The stage's loads at time t (the arrays the World would hand it).
struct Loads {
  std::vector<Vec3> force, torque;
};
inline Loads applyAt(hydro::StormLoads& stage, const World& world, double t) {
  Loads l;
  l.force.assign(world.bodies().size(), Vec3::Zero());
  l.torque.assign(world.bodies().size(), Vec3::Zero());
  stage.apply(world, t, l.force, l.torque);
  return l;
}

inline Quat someOrientation(int k) {
  return Quat(Eigen::AngleAxisd(0.3 + 0.9 * k, Vec3(1.0, 2.0 - k, 3.0 + k).normalized()));
}

inline geometry::TriangleMesh centredBox(double a, double b, double c) {
  geometry::TriangleMesh m = test::makeBox(a, b, c);
  geometry::translate(m, Vec3(-0.5 * a, -0.5 * b, -0.5 * c));
  return m;
}

// ------------------------------------------------------------------------------------------------
// A storm with variability

/// A storm with a regular oscillation of eta (amplitude 1 m, period 2 s, uniform in x) over still
/// water for the pressure, records every T/8 offset by T/16 (eta never exactly 0 at a record), and
/// a symmetric variability model: P(above) = 1/2, every class Weibull(1.5, 0.2), P_n = rho g a_n.
inline storm::StormHeader variabilityHeader() {
  storm::StormHeader h = gridHeader(-2.0, 2.0, -8.0, 1.0, 0.5, 0.0);
  h.variability.present = true;
  h.variability.probabilityAbove = {0.5, 0.5};
  for (auto& c : h.variability.classes) {
    c = {1.5, 0.2, -1.0, 0};
  }
  h.variability.normalisationElevation = 1.0;
  h.variability.normalisationPressure = kRho * kG * 1.0;
  h.variability.source = "test";
  return h;
}

inline constexpr double kWavePeriod = 2.0; // s

inline void writeVariabilityStorm(const std::string& path, int halfWaves) {
  std::vector<double> times;
  for (int r = 0; r < 4 * halfWaves + 2; ++r) {
    times.push_back((r + 0.5) * kWavePeriod / 8.0);
  }
  writeStorm(path, variabilityHeader(), times, hydrostatic(0.0),
             [](double t, double) { return std::sin(2.0 * std::numbers::pi * t / kWavePeriod); });
}

} // namespace armour::test
