// SPDX-License-Identifier: GPL-3.0-or-later
// Determinism and restart of the deformable body (issue 26): a loaded, damped, partly fixed bar of
// 10-node tets gives the same bits with 1 and 2 OpenMP threads, and a run stopped at a checkpoint
// and restarted from the file ends with the same bits as the run that went through. Damaged or
// mismatched checkpoints are refused with the file and the fix named. A VTU frame reads back in
// VTK with its fields.
#include "core/Error.hpp"
#include "deformable/DeformableCheckpoint.hpp"
#include "deformable/DeformableVtu.hpp"
#include "deformable/StressFields.hpp"
#include "support/DeformableFixtures.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cstring>
#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace armour::deformable {
namespace {

namespace fs = std::filesystem;

/// A 0.5 x 0.5 x 2 m bar, base fixed, one top corner driven sideways at 0.5 m/s, a 1 MN load on
/// another top node, gravity, viscosity 5 % of critical, and a wall (static half-space x > 0.5 m
/// - 10 um) pressing on its side: every term of the step is exercised.
DeformableBody loadedBar(ElementOrder order = ElementOrder::Quadratic) {
  DeformableSettings settings;
  settings.material.viscosity = 0.05 * criticalViscosity(settings.material, 0.25);
  settings.halfSpaces = {HalfSpace{Vec3(0.5 - 1e-5, 0.0, 0.0), -Vec3::UnitX()}};
  DeformableBody body(test::boxMesh(Vec3(0.5, 0.5, 2.0), 2, 2, 8, order), settings, "bar");
  for (const auto n : test::nodesWhere(body.mesh(), [](const Vec3& p) { return p.z() < 1e-9; })) {
    body.fixNode(n);
  }
  const auto top = test::nodesWhere(body.mesh(), [](const Vec3& p) { return p.z() > 2.0 - 1e-9; });
  body.fixNode(top.front(), Vec3(0.5, 0.0, 0.0), 1U);
  body.setExternalForce(top.back(), Vec3(0.0, 1e6, -1e6));
  return body;
}

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

/// A file in this program's scratch folder, removed when the program ends.
fs::path scratch(const std::string& name) {
  struct Folder {
    fs::path path = fs::temp_directory_path() / ("armour_deformable_" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Folder folder;
  return folder.path / name;
}

void run(DeformableBody& body, int steps) {
  const double dt = body.stableStep().dt;
  for (int s = 0; s < steps; ++s) {
    body.step(dt);
  }
}

TEST(DeformableDeterminism, OneAndTwoThreadsGiveTheSameBits) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  auto one = loadedBar();
  run(one, 80);
  omp_set_num_threads(2);
  auto two = loadedBar();
  run(two, 80);
  omp_set_num_threads(before);
  // The test is not void: the body moved and deformed. (80 steps: on a loaded 2-core machine each
  // of the step's parallel regions may wait for a time slice, so more steps cost seconds.)
  EXPECT_GT((one.positions()[one.nodeCount() - 1] - one.mesh().nodes[one.nodeCount() - 1]).norm(), 1e-5);
  EXPECT_GT(one.contactForce().norm(), 0.0);
  EXPECT_TRUE(sameBits(one.positions(), two.positions()));
  EXPECT_TRUE(sameBits(one.velocities(), two.velocities()));
  EXPECT_EQ(one.strainEnergy(), two.strainEnergy());
}

TEST(DeformableDeterminism, RestartFromACheckpointGivesTheSameBits) {
  auto straight = loadedBar();
  run(straight, 300);
  auto first = loadedBar();
  run(first, 150);
  const auto file = scratch("restart.bin");
  writeDeformableCheckpoint(first, file);
  auto resumed = loadedBar();
  readDeformableCheckpoint(file, resumed);
  EXPECT_EQ(resumed.steps(), 150U);
  run(resumed, 150);
  EXPECT_EQ(resumed.time(), straight.time());
  EXPECT_TRUE(sameBits(resumed.positions(), straight.positions()));
  EXPECT_TRUE(sameBits(resumed.velocities(), straight.velocities()));
}

std::string inputErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(DeformableDeterminism, BadCheckpointsAreRefused) {
  auto body = loadedBar();
  run(body, 10);
  const auto file = scratch("good.bin");
  writeDeformableCheckpoint(body, file);
  auto linear = loadedBar(ElementOrder::Linear);
  const auto mismatch = inputErrorOf([&] { readDeformableCheckpoint(file, linear); });
  EXPECT_NE(mismatch.find(file.string() + ": written for"), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("restart with the mesh and element order"), std::string::npos) << mismatch;
  const auto truncated = scratch("truncated.bin");
  fs::copy_file(file, truncated, fs::copy_options::overwrite_existing);
  fs::resize_file(truncated, fs::file_size(file) - 100);
  EXPECT_NE(inputErrorOf([&] { readDeformableCheckpoint(truncated, body); }).find("truncated"), std::string::npos);
  const auto text = scratch("text.bin");
  std::ofstream(text) << "not a checkpoint at all, just some text";
  EXPECT_NE(inputErrorOf([&] { readDeformableCheckpoint(text, body); }).find("not a deformable-body checkpoint"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] { readDeformableCheckpoint(scratch("missing.bin"), body); }).find("cannot open"),
            std::string::npos);
}

TEST(DeformableDeterminism, ACheckpointOfAnotherSetupIsRefusedNamingTheChange) {
  // Same mesh counts, other material: before format version 3 this continued silently with the
  // new material. Now the first changed line of the setup is named, and the body is untouched.
  auto body = loadedBar();
  run(body, 10);
  const auto file = scratch("setup.bin");
  writeDeformableCheckpoint(body, file);
  DeformableSettings stiffer = body.settings();
  stiffer.material.youngModulus = 30e9;
  DeformableBody other(body.mesh(), stiffer, "bar");
  const auto message = inputErrorOf([&] { readDeformableCheckpoint(file, other); });
  EXPECT_NE(message.find("was written for another setup: 'material.young_modulus = 26600000000 Pa' then, "
                         "'material.young_modulus = 30000000000 Pa' now"),
            std::string::npos)
      << message;
  EXPECT_EQ(other.steps(), 0u);
  // A mesh with one node moved by 1 mm: the mesh line differs.
  DeformableMesh moved = body.mesh();
  moved.nodes[5].x() += 1e-3;
  DeformableBody shifted(moved, body.settings(), "bar");
  EXPECT_NE(inputErrorOf([&] { readDeformableCheckpoint(file, shifted); }).find("'mesh = "), std::string::npos);
  // The same setup reads (and a mass-scaling change is refused too).
  DeformableBody same(body.mesh(), body.settings(), "bar");
  EXPECT_NO_THROW(readDeformableCheckpoint(file, same));
  DeformableSettings scaled = body.settings();
  scaled.massScaling = 0.01;
  DeformableBody heavier(body.mesh(), scaled, "bar");
  EXPECT_NE(inputErrorOf([&] { readDeformableCheckpoint(file, heavier); }).find("'mass_scaling = 0' then"),
            std::string::npos);
}

TEST(DeformableDeterminism, VtuFrameReadsBackWithItsFields) {
  auto body = loadedBar();
  run(body, 50);
  const auto file = scratch("frame.vtu");
  writeDeformableVtu(body, file);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  auto* grid = reader->GetOutput();
  ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(body.mesh().elementCount()));
  ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(body.nodeCount()));
  EXPECT_EQ(grid->GetCellType(0), VTK_QUADRATIC_TETRA);
  for (const char* name : {"displacement", "velocity", "cauchy_stress", "sigma_1", "sigma_3", "differential_stress",
                           "von_mises"}) {
    EXPECT_NE(grid->GetPointData()->GetArray(name), nullptr) << name;
  }
  auto* vonMises = grid->GetCellData()->GetArray("von_mises");
  ASSERT_NE(vonMises, nullptr);
  const auto stresses = body.elementStresses();
  for (const std::size_t e : {std::size_t{0}, body.mesh().elementCount() - 1}) {
    EXPECT_EQ(vonMises->GetTuple1(static_cast<vtkIdType>(e)), summarizeStress(stresses[e]).vonMises);
  }
  const auto last = static_cast<vtkIdType>(body.nodeCount() - 1);
  const Vec3 displacement = body.positions().back() - body.mesh().nodes.back();
  EXPECT_EQ(grid->GetPointData()->GetArray("displacement")->GetTuple3(last)[2], displacement.z());
}

} // namespace
} // namespace armour::deformable
