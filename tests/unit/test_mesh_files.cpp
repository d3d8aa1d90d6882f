// SPDX-License-Identifier: GPL-3.0-or-later
// Mesh files: round trips keep the solid (STL binary to float precision, the others exactly), and
// broken files give errors that name the file (and the line where there is one).

#include "core/Error.hpp"
#include "geometry/MassProperties.hpp"
#include "geometry/MeshFile.hpp"
#include "geometry/MeshValidation.hpp"
#include "geometry/StlFile.hpp"
#include "support/TestMeshes.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace armour::geometry;
using armour::core::InputError;
namespace fs = std::filesystem;

namespace {

class MeshFiles : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("armour-mesh-files-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // A box away from the origin with non-representable coordinates.
    box_ = armour::test::makeBox(1.1, 2.3, 0.7);
    translate(box_, Vec3(10.1, -3.3, 7.7));
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path file(const std::string& name) const { return dir_ / name; }
  void writeText(const fs::path& path, const std::string& text) const { std::ofstream(path) << text; }

  /// Expect readMesh to throw an InputError whose message contains every fragment.
  void expectReadError(const fs::path& path, std::initializer_list<std::string> fragments) const {
    try {
      readMesh(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      for (const auto& f : fragments) {
        EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << "missing '" << f << "' in: " << e.what();
      }
    }
  }

  fs::path dir_;
  TriangleMesh box_;
};

} // namespace

TEST_F(MeshFiles, RoundTripsKeepTheSolid) {
  const double volume = computeMassProperties(box_).volume;
  // Binary STL stores float32 corners: relative error ~ 6e-8 per coordinate, so 1e-6 on volume.
  const std::vector<std::pair<std::string, double>> cases = {
      {"box.stl", 1e-6}, {"box-ascii.stl", 1e-14}, {"box.obj", 1e-14}, {"box.vtp", 1e-14}};
  for (const auto& [name, tolerance] : cases) {
    const MeshFormat format = name == "box-ascii.stl" ? MeshFormat::StlAscii : meshFormatFromPath(name);
    writeMesh(box_, file(name), format);
    TriangleMesh back = readMesh(file(name));
    EXPECT_EQ(back.vertexCount(), 8u) << name << ": STL corners must be welded";
    EXPECT_EQ(back.triangleCount(), 12u) << name;
    EXPECT_NO_THROW(validateMesh(back, name));
    EXPECT_NEAR(computeMassProperties(back).volume, volume, tolerance * volume) << name;
  }
}

TEST_F(MeshFiles, AtomicWriteLeavesNoTemporary) {
  writeMesh(box_, file("a.obj"), MeshFormat::Obj);
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir_)) {
    ++count;
  }
  EXPECT_EQ(count, 1u);
}

TEST_F(MeshFiles, ObjPolygonsAndNegativeIndices) {
  // A unit cube written as quads with relative (negative) indices and v/vt/vn forms.
  writeText(file("quads.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                               "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2/1/1 3/1/1 7/1/1 6/1/1\nf 3 4 8 7\nf -8 -4 -1 -5\n");
  TriangleMesh cube = readMesh(file("quads.obj"));
  EXPECT_EQ(cube.triangleCount(), 12u);
  validateMesh(cube, "quads.obj");
  EXPECT_NEAR(computeMassProperties(cube).volume, 1.0, 1e-14);
}

TEST_F(MeshFiles, MissingFileAndUnknownExtension) {
  expectReadError(file("nope.stl"), {"nope.stl", "cannot open"});
  writeText(file("unit.ply"), "ply\n");
  expectReadError(file("unit.ply"), {"unit.ply", "'.ply'", ".stl, .obj or .vtp"});
}

TEST_F(MeshFiles, TruncatedBinaryStl) {
  writeMesh(box_, file("cut.stl"), MeshFormat::Stl);
  fs::resize_file(file("cut.stl"), 84 + 50 * 5 + 7);
  expectReadError(file("cut.stl"), {"cut.stl", "truncated", "12 triangles"});
}

TEST_F(MeshFiles, AsciiStlErrorsNameTheLine) {
  writeText(file("bad.stl"), "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 zero 0\n");
  expectReadError(file("bad.stl"), {"bad.stl:5", "vertex"});
  writeText(file("quad.stl"), "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n"
                              " vertex 1 1 0\n vertex 0 1 0\n endloop\n endfacet\nendsolid\n");
  expectReadError(file("quad.stl"), {"quad.stl:8", "4 vertices"});
  writeText(file("open.stl"), "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n");
  expectReadError(file("open.stl"), {"open.stl", "truncated"});
}

TEST_F(MeshFiles, BinaryStlWhoseHeaderStartsWithSolid) {
  // Some exporters write "solid" at the start of a binary header; the exact size decides.
  writeMesh(box_, file("solid.stl"), MeshFormat::Stl);
  {
    std::fstream f(file("solid.stl"), std::ios::in | std::ios::out | std::ios::binary);
    f.write("solid binary", 12);
  }
  EXPECT_EQ(readMesh(file("solid.stl")).triangleCount(), 12u);
}

TEST_F(MeshFiles, ObjErrorsNameTheLine) {
  writeText(file("idx.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expectReadError(file("idx.obj"), {"idx.obj:4", "vertex 9", "3 vertices"});
  writeText(file("zero.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expectReadError(file("zero.obj"), {"zero.obj:4", "'0'"});
  writeText(file("v.obj"), "v 0 0\n");
  expectReadError(file("v.obj"), {"v.obj:1", "v x y z"});
  writeText(file("empty.obj"), "# nothing\n");
  expectReadError(file("empty.obj"), {"empty.obj", "no faces"});
}

TEST_F(MeshFiles, CorruptVtp) {
  writeText(file("bad.vtp"), "<VTKFile type=\"PolyData\"><PolyData><Piece NumberOfPoints=\"3\">garbage");
  expectReadError(file("bad.vtp"), {"bad.vtp"});
}

TEST(MeshFormats, Names) {
  EXPECT_EQ(meshFormatFromName("obj"), MeshFormat::Obj);
  EXPECT_EQ(meshFormatFromPath("A/B/Unit.STL"), MeshFormat::Stl);
  try {
    meshFormatFromName("ply");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stl, stl-ascii, obj or vtp"), std::string::npos);
  }
}

TEST(MeshFilesInAChild, DamagedCompressedVtpIsRefusedInsteadOfCrashingVtk) {
  // VTK 9.1 dies with SIGSEGV in vtkXMLDataParser::ReadBlock on this compressed .vtp with flipped
  // bytes (tests/fuzz/upstream, found by the fuzz pass). readVtp reads it in a child first: the
  // crash becomes an input error naming the file, the library, the signal and the fix.
  const std::string path = std::string(ARMOUR_TEST_DATA) + "/../fuzz/upstream/vtk-9.1-readblock-sigsegv.vtp";
  try {
    (void)armour::geometry::readMesh(path);
    FAIL() << "the damaged .vtp was read";
  } catch (const armour::core::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vtk-9.1-readblock-sigsegv.vtp"), std::string::npos) << what;
    EXPECT_NE(what.find("crashed the VTK library with signal 11"), std::string::npos) << what;
    EXPECT_NE(what.find("re-export it"), std::string::npos) << what;
  }
}
