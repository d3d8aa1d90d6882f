// SPDX-License-Identifier: GPL-3.0-or-later
// Checkpoints (simulation/CheckpointFile): a World stepped N steps, captured, written to
// checkpoint.nc, read back and restored into a freshly built World continues M steps to exactly
// (bit for bit) the state of an uninterrupted run of N + M steps - with a cube sliding on the
// floor (friction springs that slide), and later with sleeping bodies beside awake ones. Leaving
// out the friction springs does change the result, so the comparison can fail. The file round
// trip is exact for every field; the scene fingerprint ignores the duration and the output
// settings but not materials, bodies or the time step. Bad inputs (missing, garbage or cut
// short files, a netCDF file that is not a checkpoint, another format version, a missing
// variable, a non-finite state, another scene, another body count) give InputErrors that name
// the file and the problem.
//
// Tolerance: none. A restart must continue bit for bit, so doubles are compared by their bits.

#include "core/Error.hpp"
#include "io/SceneReader.hpp"
#include "simulation/CheckpointFile.hpp"
#include "simulation/SceneBuilder.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netcdf.h>
#include <omp.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

using namespace armour;
using namespace armour::simulation;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(ARMOUR_TEST_DATA) / "scenes";

/// One OpenMP thread: the World's results do not depend on the thread count (World.hpp), and on
/// a shared machine two threads on a few small contact pairs mostly wait for each other.
class OneThread : public ::testing::Environment {
  void SetUp() override { omp_set_num_threads(1); }
};
[[maybe_unused]] const ::testing::Environment* const kOneThread = ::testing::AddGlobalTestEnvironment(new OneThread);

/// tests/data/scenes/restart.yaml: a sliding cube, a tumbling cube and a stack that falls asleep.
io::Scene restartScene() { return io::readScene(kScenes / "restart.yaml"); }

/// A fresh folder per test.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("armour_test_checkpoint_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool sameBits(const Vec3& a, const Vec3& b) {
  return sameBits(a.x(), b.x()) && sameBits(a.y(), b.y()) && sameBits(a.z(), b.z());
}
bool sameBits(const Quat& a, const Quat& b) {
  return sameBits(a.w(), b.w()) && sameBits(a.x(), b.x()) && sameBits(a.y(), b.y()) && sameBits(a.z(), b.z());
}

/// The first field in which two states differ ("" if none): every bit of every field.
std::string firstDifference(const WorldState& a, const WorldState& b) {
  if (!sameBits(a.time, b.time)) return fmt::format("time {} vs {}", a.time, b.time);
  if (a.steps != b.steps) return fmt::format("steps {} vs {}", a.steps, b.steps);
  if (a.forcesReady != b.forcesReady) return "forcesReady";
  if (!sameBits(a.energyMinimum, b.energyMinimum)) return "energyMinimum";
  if (!sameBits(a.externalWork, b.externalWork)) return "externalWork";
  if (!sameBits(a.energyPeak, b.energyPeak)) return "energyPeak";
  if (a.energyStarted != b.energyStarted) return "energyStarted";
  if (a.bodies.size() != b.bodies.size()) return "body count";
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyState& x = a.bodies[i];
    const BodyState& y = b.bodies[i];
    const auto at = [i](const char* what) { return fmt::format("body {}: {}", i, what); };
    if (x.motion != y.motion) return at("motion type");
    if (!sameBits(x.position, y.position)) return at("position");
    if (!sameBits(x.orientation, y.orientation)) return at("orientation");
    if (!sameBits(x.velocity, y.velocity)) return at("velocity");
    if (!sameBits(x.angularMomentum, y.angularMomentum)) return at("angular momentum");
    if (!sameBits(x.force, y.force)) return at("force");
    if (!sameBits(x.torque, y.torque)) return at("torque");
    if (!sameBits(x.restTime, y.restTime)) return at("rest time");
    if (x.contactCount != y.contactCount) return at("contact count");
    if (!sameBits(x.maxContactForce, y.maxContactForce)) return at("max contact force");
  }
  if (a.contacts.size() != b.contacts.size()) {
    return fmt::format("contact count {} vs {}", a.contacts.size(), b.contacts.size());
  }
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    const ContactPointState& x = a.contacts[k];
    const ContactPointState& y = b.contacts[k];
    if (x.first != y.first || x.second != y.second || x.key != y.key || x.sliding != y.sliding ||
        !sameBits(x.stretch, y.stretch)) {
      return fmt::format("contact {}", k);
    }
  }
  return {};
}

void stepN(World& world, int n) {
  for (int i = 0; i < n; ++i) {
    world.step();
  }
}

/// A checkpoint of `world` as armour run writes it.
Checkpoint checkpointOf(const World& world, const io::Scene& scene) {
  Checkpoint c;
  c.state = world.captureState();
  c.sceneIdentity = sceneIdentity(scene);
  c.sceneFingerprint = fingerprintOf(c.sceneIdentity);
  for (BodyId b = 0; b < world.bodies().size(); ++b) {
    c.bodyNames.push_back(world.bodies().info(b).name);
  }
  c.outputs = {0.25, 0.19};
  return c;
}

/// The message of the InputError that `f` throws ("" if it throws none).
template <typename F>
std::string inputError(F&& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return {};
}

std::size_t countSliding(const WorldState& s) {
  std::size_t n = 0;
  for (const auto& c : s.contacts) n += c.sliding ? 1 : 0;
  return n;
}

std::size_t countMotion(const WorldState& s, dynamics::MotionType type) {
  std::size_t n = 0;
  for (const auto& b : s.bodies) n += b.motion == type ? 1 : 0;
  return n;
}

// ---------------------------------------------------------------------------------------------
// Restart is bit for bit
// ---------------------------------------------------------------------------------------------

TEST(CheckpointRestart, ContinuesBitForBitWhileSlidingAndWithSleepingBodies) {
  const io::Scene scene = restartScene();
  const fs::path dir = scratch("restart");
  BuiltScene uninterrupted = buildWorld(scene);
  World& a = *uninterrupted.world;
  const double dt = a.timeStep();
  // Continue for 0.1 s: past two energy-guard checks (every 50 steps) and many contact changes.
  const int more = static_cast<int>(std::ceil(0.1 / dt));

  // Two restart points: t = 0.2 s, the slider sliding (its friction springs slide); t = 1.5 s,
  // the stack asleep (rest timers, sleeping bodies that keep their springs) beside awake bodies.
  struct Point {
    double time;
    const char* what;
  };
  int done = 0;
  for (const Point point : {Point{0.2, "sliding"}, Point{1.5, "sleeping"}}) {
    const int n = static_cast<int>(std::ceil(point.time / dt)) - done;
    stepN(a, n);
    const Checkpoint written = checkpointOf(a, scene);
    if (std::string(point.what) == "sliding") {
      ASSERT_GT(countSliding(written.state), 0u) << "the slider should be sliding at t = 0.2 s";
    } else {
      ASSERT_GT(countMotion(written.state, dynamics::MotionType::Sleeping), 0u) << "no body asleep at t = 1.5 s";
      ASSERT_GT(countMotion(written.state, dynamics::MotionType::Dynamic), 0u) << "no body awake at t = 1.5 s";
    }
    const fs::path file = dir / fmt::format("checkpoint_{}.nc", point.what);
    writeCheckpoint(file, written);
    stepN(a, more);
    const WorldState reference = a.captureState();
    done += n + more;

    const Checkpoint read = readCheckpoint(file, {written.sceneFingerprint, written.sceneIdentity, a.bodies().size()});
    BuiltScene fresh = buildWorld(scene);
    fresh.world->restoreState(read.state);
    stepN(*fresh.world, more);
    EXPECT_EQ(firstDifference(fresh.world->captureState(), reference), "")
        << point.what << ": the restarted run differs from the uninterrupted one (bit for bit)";

    // The comparison can fail: without the friction springs the continuation is different.
    WorldState forgetful = read.state;
    forgetful.contacts.clear();
    BuiltScene other = buildWorld(scene);
    other.world->restoreState(forgetful);
    stepN(*other.world, more);
    EXPECT_NE(firstDifference(other.world->captureState(), reference), "")
        << point.what << ": dropping the friction springs should change the result";
  }
  fs::remove_all(dir);
}

TEST(CheckpointRestart, RestoringTwiceFromTheSameCheckpointGivesTheSameRun) {
  // The restored World must not depend on anything the fresh build leaves behind: two restores
  // (one into a World that has already run) continue identically.
  const io::Scene scene = restartScene();
  BuiltScene built = buildWorld(scene);
  World& a = *built.world;
  stepN(a, 2000);
  const WorldState saved = a.captureState();
  stepN(a, 1000);
  a.restoreState(saved); // the same World, rewound
  stepN(a, 500);
  BuiltScene fresh = buildWorld(scene);
  fresh.world->restoreState(saved);
  stepN(*fresh.world, 500);
  EXPECT_EQ(firstDifference(a.captureState(), fresh.world->captureState()), "");
}

// ---------------------------------------------------------------------------------------------
// The file
// ---------------------------------------------------------------------------------------------

TEST(CheckpointFile, RoundTripIsExact) {
  const io::Scene scene = restartScene();
  const fs::path dir = scratch("roundtrip");
  BuiltScene built = buildWorld(scene);
  // Before the first step: no contacts, forces not ready (the zero-length contact dimension).
  for (int steps : {0, 3000}) {
    stepN(*built.world, steps);
    Checkpoint c = checkpointOf(*built.world, scene);
    c.stopReason = steps == 0 ? "" : "a test reason";
    writeCheckpoint(dir / "checkpoint.nc", c);
    EXPECT_FALSE(fs::exists(dir / fmt::format("checkpoint.nc.tmp.{}", ::getpid()))) << "temporary file left behind";
    const Checkpoint r = readCheckpoint(dir / "checkpoint.nc");
    EXPECT_EQ(firstDifference(r.state, c.state), "") << "after " << steps << " steps";
    EXPECT_EQ(r.state.contacts.size(), c.state.contacts.size());
    if (steps > 0) {
      EXPECT_GT(r.state.contacts.size(), 0u) << "the cubes should touch the floor after 3000 steps";
    }
    EXPECT_EQ(r.sceneFingerprint, c.sceneFingerprint);
    EXPECT_EQ(r.sceneIdentity, c.sceneIdentity);
    EXPECT_EQ(r.bodyNames, c.bodyNames);
    EXPECT_TRUE(sameBits(r.outputs.lastVtkTime, 0.25) && sameBits(r.outputs.lastSeriesTime, 0.19));
    EXPECT_EQ(r.stopReason, c.stopReason);
    EXPECT_EQ(r.formatVersion, kCheckpointFormatVersion);
    EXPECT_NE(r.build.find("armour"), std::string::npos) << r.build;
  }
  fs::remove_all(dir);
}

TEST(CheckpointFile, FingerprintIgnoresDurationAndOutputsOnly) {
  const io::Scene scene = restartScene();
  const std::string base = sceneFingerprint(scene);
  EXPECT_EQ(base.rfind("fnv1a64:", 0), 0u) << base;
  EXPECT_EQ(base.size(), 8u + 16u) << base;

  io::Scene longer = scene;
  longer.duration *= 3.0;
  longer.output.folder = "/elsewhere";
  longer.output.vtkInterval = 0.0;
  longer.output.seriesInterval = 0.5;
  longer.output.checkpointInterval = 7.0;
  longer.sourceName = "renamed.yaml";
  longer.name = "renamed";
  longer.description = "another description";
  EXPECT_EQ(sceneFingerprint(longer), base) << "duration, outputs and the file name may change for a restart";

  io::Scene friction = scene;
  friction.materials[0].frictionStatic = friction.materials[0].frictionDynamic = 0.6;
  io::Scene step = scene;
  step.timeStep.automatic = false;
  step.timeStep.value = 1e-5;
  io::Scene moved = scene;
  moved.bodies[1].position.x() += 1e-12;
  io::Scene gravity = scene;
  gravity.gravity.z() = -9.8;
  io::Scene sleep = scene;
  sleep.sleep.time = 0.4;
  for (const auto* changed : {&friction, &step, &moved, &gravity, &sleep}) {
    EXPECT_NE(sceneFingerprint(*changed), base);
  }
}

TEST(CheckpointFile, BadInputsNameTheFileAndTheProblem) {
  const io::Scene scene = restartScene();
  const fs::path dir = scratch("bad");
  BuiltScene built = buildWorld(scene);
  stepN(*built.world, 500);
  const Checkpoint good = checkpointOf(*built.world, scene);
  const fs::path goodFile = dir / "good.nc";
  writeCheckpoint(goodFile, good);
  const auto expectMessage = [](const std::string& message, const fs::path& file,
                                std::initializer_list<const char*> parts) {
    ASSERT_FALSE(message.empty()) << "no InputError for " << file;
    EXPECT_NE(message.find(file.string()), std::string::npos) << "the file is not named: " << message;
    for (const char* part : parts) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing from: " << message;
    }
  };
  const auto copyOf = [&](const std::string& name) {
    const fs::path file = dir / name;
    fs::copy_file(goodFile, file, fs::copy_options::overwrite_existing);
    return file;
  };

  // Missing.
  const fs::path missing = dir / "missing.nc";
  expectMessage(inputError([&] { (void)readCheckpoint(missing); }), missing, {"no checkpoint", "--restart"});

  // Garbage and a file cut short.
  const fs::path garbage = dir / "garbage.nc";
  std::ofstream(garbage) << "this is not a netCDF file\n";
  expectMessage(inputError([&] { (void)readCheckpoint(garbage); }), garbage, {"damaged"});
  const fs::path cut = copyOf("cut.nc");
  fs::resize_file(cut, fs::file_size(cut) / 2);
  expectMessage(inputError([&] { (void)readCheckpoint(cut); }), cut, {"damaged"});

  // A netCDF file that is not a checkpoint.
  const fs::path other = dir / "other.nc";
  int ncid = -1;
  ASSERT_EQ(nc_create(other.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid), NC_NOERR);
  ASSERT_EQ(nc_close(ncid), NC_NOERR);
  expectMessage(inputError([&] { (void)readCheckpoint(other); }), other,
                {"not an armour checkpoint", "armour_checkpoint_version"});

  // Another format version.
  const fs::path version = copyOf("version.nc");
  ASSERT_EQ(nc_open(version.c_str(), NC_WRITE, &ncid), NC_NOERR);
  ASSERT_EQ(nc_redef(ncid), NC_NOERR);
  const int future = 99;
  ASSERT_EQ(nc_put_att_int(ncid, NC_GLOBAL, "armour_checkpoint_version", NC_INT, 1, &future), NC_NOERR);
  ASSERT_EQ(nc_close(ncid), NC_NOERR);
  expectMessage(inputError([&] { (void)readCheckpoint(version); }), version, {"armour_checkpoint_version = 99"});

  // Parts missing: a file with the checkpoint's global attributes but no dimensions or variables.
  const fs::path hollow = dir / "hollow.nc";
  int from = -1, natts = 0;
  ASSERT_EQ(nc_open(goodFile.c_str(), NC_NOWRITE, &from), NC_NOERR);
  ASSERT_EQ(nc_create(hollow.c_str(), NC_NETCDF4 | NC_CLOBBER, &ncid), NC_NOERR);
  ASSERT_EQ(nc_inq_natts(from, &natts), NC_NOERR);
  for (int k = 0; k < natts; ++k) {
    char name[NC_MAX_NAME + 1];
    ASSERT_EQ(nc_inq_attname(from, NC_GLOBAL, k, name), NC_NOERR);
    ASSERT_EQ(nc_copy_att(from, NC_GLOBAL, name, ncid, NC_GLOBAL), NC_NOERR);
  }
  ASSERT_EQ(nc_close(ncid), NC_NOERR);
  ASSERT_EQ(nc_close(from), NC_NOERR);
  expectMessage(inputError([&] { (void)readCheckpoint(hollow); }), hollow, {"dimension 'body'", "missing", "damaged"});

  // A non-finite state (what a guard-rail stop may write): refused, the body and variable named.
  Checkpoint blown = good;
  blown.state.bodies[2].velocity.y() = std::numeric_limits<double>::quiet_NaN();
  const fs::path nan = dir / "nan.nc";
  writeCheckpoint(nan, blown);
  expectMessage(inputError([&] { (void)readCheckpoint(nan); }), nan,
                {"variable 'velocity'", "body 'base'", "not finite"});

  // Another scene: the fingerprint differs, and the first changed line is named.
  io::Scene changed = scene;
  changed.materials[0].frictionStatic = changed.materials[0].frictionDynamic = 0.6;
  const std::string identity = sceneIdentity(changed);
  expectMessage(inputError([&] { (void)readCheckpoint(goodFile, {fingerprintOf(identity), identity, 0}); }), goodFile,
                {"scene_fingerprint", "scene changed", "friction static = 0.5", "friction static = 0.6"});

  // Another body count, seen by the reader and by World::restoreState.
  expectMessage(inputError([&] { (void)readCheckpoint(goodFile, {"", "", 3}); }), goodFile,
                {"dimension 'body' = 4", "scene builds 3"});
  io::Scene fewer = scene;
  fewer.bodies.pop_back();
  BuiltScene small = buildWorld(fewer);
  const std::string restoreMessage = inputError([&] { small.world->restoreState(good.state); });
  EXPECT_NE(restoreMessage.find("holds 4 bodies but the scene builds 3"), std::string::npos) << restoreMessage;

  // An unwritable place.
  const fs::path nowhere = dir / "no-such-folder" / "checkpoint.nc";
  expectMessage(inputError([&] { writeCheckpoint(nowhere, good); }), nowhere, {"could not create"});
  fs::remove_all(dir);
}

} // namespace
