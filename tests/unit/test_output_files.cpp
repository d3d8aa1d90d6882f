// SPDX-License-Identifier: GPL-3.0-or-later
// Output files: the VTK frames put every body's surface where p = x + q (s p_body) says, carry
// the per-body arrays and the displacement from the first frame, are listed in a .pvd that VTK's
// own XML parser reads back with the exact times, and resume keeps the frames up to the restart
// time and numbers on. The netCDF body series has the documented dimensions, CF attributes,
// chunking and compression, holds the values bit for bit, survives a kill after a flush, and
// resume keeps the records up to the restart time. Unwritable folders give InputErrors naming them.

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"
#include "geometry/ShapeLibrary.hpp"
#include "io/BodySeriesFile.hpp"
#include "io/VtkFrameWriter.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netcdf.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUtilities.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using armour::core::InputError;
using armour::geometry::TriangleMesh;
using armour::geometry::Vec3;
using namespace armour::io;

constexpr int kBodies = 3;
constexpr int kFrames = 5;

/// Output times 0.05 + 0.1 k: not binary fractions, so the .pvd must print them round-trip exact.
double frameTime(int k) { return 0.05 + 0.1 * k; }

/// Three cubes of different sizes and orientations, moving and turning from frame to frame.
/// Ids are not indices (10, 11, 12) so that a writer mixing the two is caught.
class Motion {
public:
  Motion() : cube_(armour::geometry::makeShape("cube", {})) {}

  [[nodiscard]] BodyFrame frame(int k, double time) const {
    BodyFrame f;
    f.time = time;
    for (int i = 0; i < kBodies; ++i) {
      BodySnapshot b;
      b.id = 10 + i;
      b.position = position(i, k);
      b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * i + 0.2 * k, Vec3(1.0, 2.0 + i, 3.0).normalized()));
      b.velocity = Vec3(0.1 * i - 0.7, 1.3 + k, -0.2 * k);
      b.angularVelocity = Vec3(0.5, -0.25 * i, 0.125 * k + 0.01);
      b.contactCount = i + k;
      b.maxContactForce = 1000.0 * (i + 1) + 3.7 * k;
      b.surface = &cube_;
      b.scale = 0.5 + 0.75 * i;
      f.bodies.push_back(b);
    }
    return f;
  }
  [[nodiscard]] BodyFrame frame(int k) const { return frame(k, frameTime(k)); }

  /// Centres far from the origin (x ~ 100 m), where round-off in the transform would show.
  [[nodiscard]] static Vec3 position(int i, int k) {
    return Vec3(100.0 + 3.1 * i + 0.013 * k, -7.3 + 0.7 * i, 2.45 - 0.011 * k * k);
  }

  [[nodiscard]] static std::vector<ContactPoint> contacts(int k) {
    return {{Vec3(100.5, -7.0, 2.0 + k), Vec3(10.0 * k, -1.5, 300.0), 300.25, 10, 11},
            {Vec3(103.0, -6.5, 1.5), Vec3(0.0, 2.0, 150.0 + k), 150.0 + k, 11, -1}};
  }

  [[nodiscard]] static std::vector<SeriesBody> table() {
    return {{10, "unit_0"}, {11, "unit_long_name_1"}, {12, "u2"}};
  }

  const TriangleMesh& cube() const { return cube_; }

private:
  TriangleMesh cube_;
};

class OutputFiles : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("armour-output-files-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  Motion motion_;
};

vtkSmartPointer<vtkPolyData> readPolyData(const fs::path& path) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkSmartPointer<vtkPolyData> data = reader->GetOutput();
  return data;
}

/// (timestep, file) of every DataSet, parsed by VTK's XML parser, as ParaView would.
std::vector<std::pair<double, std::string>> collectionByVtk(const fs::path& pvd) {
  vtkSmartPointer<vtkXMLDataElement> root;
  root.TakeReference(vtkXMLUtilities::ReadElementFromFile(pvd.c_str()));
  std::vector<std::pair<double, std::string>> out;
  if (!root) {
    ADD_FAILURE() << "VTK cannot parse " << pvd;
    return out;
  }
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  if (collection == nullptr) {
    ADD_FAILURE() << "no Collection element in " << pvd;
    return out;
  }
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    EXPECT_STREQ(e->GetName(), "DataSet");
    out.emplace_back(std::stod(e->GetAttribute("timestep")), e->GetAttribute("file"));
  }
  return out;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<double> tuple(vtkDataArray* a, vtkIdType i) {
  std::vector<double> v(static_cast<std::size_t>(a->GetNumberOfComponents()));
  a->GetTuple(i, v.data());
  return v;
}

std::vector<double> components(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

/// Check one bodies frame against the motion at frame k (displacement measured from frame 0).
void expectBodiesFrame(const fs::path& path, const Motion& motion, int k) {
  SCOPED_TRACE(path.string());
  auto data = readPolyData(path);
  const auto& cube = motion.cube();
  const auto nv = static_cast<vtkIdType>(cube.vertexCount());
  const auto nt = static_cast<vtkIdType>(cube.triangleCount());
  ASSERT_EQ(data->GetNumberOfPoints(), kBodies * nv);
  ASSERT_EQ(data->GetNumberOfPolys(), kBodies * nt);
  const BodyFrame frame = motion.frame(k);
  vtkPointData* pd = data->GetPointData();
  for (const char* name : {"body_id", "velocity", "speed", "angular_velocity", "contact_count", "max_contact_force",
                           "displacement"}) {
    ASSERT_NE(pd->GetArray(name), nullptr) << name;
    ASSERT_EQ(pd->GetArray(name)->GetNumberOfTuples(), kBodies * nv) << name;
  }
  for (int i = 0; i < kBodies; ++i) {
    const auto& b = frame.bodies[static_cast<std::size_t>(i)];
    for (vtkIdType v = 0; v < nv; ++v) {
      const vtkIdType p = i * nv + v;
      // Independent of the writer's rotation matrix: Eigen's quaternion-vector product. Both are
      // a few roundings of values ~100 m, so they agree to ~1e-14 m; 1e-12 m is that with margin.
      const Vec3 expected = b.position + b.orientation * (b.scale * cube.vertices[static_cast<std::size_t>(v)]);
      double got[3];
      data->GetPoint(p, got);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got[c], expected[c], 1e-12) << "body " << i << " vertex " << v;
      }
      // Per-body values are copies (or, for speed and displacement, the same double operation),
      // so they must come back bit for bit: the files hold float64 and zlib is lossless.
      EXPECT_EQ(pd->GetArray("body_id")->GetTuple1(p), b.id);
      EXPECT_EQ(tuple(pd->GetArray("velocity"), p), components(b.velocity));
      EXPECT_EQ(pd->GetArray("speed")->GetTuple1(p), b.velocity.norm());
      EXPECT_EQ(tuple(pd->GetArray("angular_velocity"), p), components(b.angularVelocity));
      EXPECT_EQ(pd->GetArray("contact_count")->GetTuple1(p), b.contactCount);
      EXPECT_EQ(pd->GetArray("max_contact_force")->GetTuple1(p), b.maxContactForce);
      EXPECT_EQ(tuple(pd->GetArray("displacement"), p), components(b.position - Motion::position(i, 0)));
    }
  }
  // Triangles keep their corner order (outward normals) with the body's vertex offset.
  vtkCellArray* polys = data->GetPolys();
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  vtkIdType cell = 0;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids); ++cell) {
    ASSERT_EQ(n, 3);
    const auto body = cell / nt;
    const auto& t = cube.triangles[static_cast<std::size_t>(cell % nt)];
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(ids[c], body * nv + t[static_cast<std::size_t>(c)]);
    }
  }
  vtkDataArray* time = data->GetFieldData()->GetArray("TimeValue");
  ASSERT_NE(time, nullptr);
  EXPECT_EQ(time->GetTuple1(0), frame.time);
}

void writeFrames(VtkFrameWriter& writer, const Motion& motion, int from, int to) {
  for (int k = from; k < to; ++k) {
    const auto contacts = Motion::contacts(k);
    writer.write(motion.frame(k), contacts);
  }
}

VtkFrameSettings vtkSettings(const fs::path& folder, bool contacts = false, std::optional<double> resumeTime = {}) {
  VtkFrameSettings s;
  s.folder = folder;
  s.contacts = contacts;
  s.resumeTime = resumeTime;
  return s;
}

BodySeriesSettings seriesSettings(const fs::path& path, const std::string& history = "",
                                  std::optional<double> resumeTime = {}, std::size_t syncEvery = 16) {
  BodySeriesSettings s;
  s.path = path;
  s.history = history;
  s.resumeTime = resumeTime;
  s.syncEvery = syncEvery;
  return s;
}

template <typename F>
std::string inputErrorFrom(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

} // namespace

// ---------------------------------------------------------------------------------------------
// VTK frames
// ---------------------------------------------------------------------------------------------

TEST_F(OutputFiles, VtkFramesHoldWorldSurfacesAndArrays) {
  {
    VtkFrameWriter writer(vtkSettings(dir_, true));
    writeFrames(writer, motion_, 0, kFrames);
    EXPECT_EQ(writer.frameCount(), static_cast<std::size_t>(kFrames));
  }
  const auto listed = collectionByVtk(dir_ / "bodies.pvd");
  ASSERT_EQ(listed.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    // Exact: the .pvd prints the shortest text that reads back to the same double.
    EXPECT_EQ(listed[static_cast<std::size_t>(k)].first, frameTime(k));
    const fs::path file = dir_ / listed[static_cast<std::size_t>(k)].second;
    ASSERT_TRUE(fs::is_regular_file(file)) << file;
    expectBodiesFrame(file, motion_, k);
  }
  EXPECT_EQ(listed[3].second, "bodies/frame_000003.vtp");

  // Appended binary, zlib, float64 points: what the shared VTK writer promises.
  const std::string head = readText(dir_ / "bodies" / "frame_000000.vtp").substr(0, 4000);
  EXPECT_NE(head.find("vtkZLibDataCompressor"), std::string::npos);
  EXPECT_NE(head.find("format=\"appended\""), std::string::npos);

  // Contacts: one vertex cell per point, force vectors and ids as given.
  const auto contactList = collectionByVtk(dir_ / "contacts.pvd");
  ASSERT_EQ(contactList.size(), static_cast<std::size_t>(kFrames));
  auto contacts = readPolyData(dir_ / contactList[2].second);
  const auto expected = Motion::contacts(2);
  ASSERT_EQ(contacts->GetNumberOfPoints(), 2);
  EXPECT_EQ(contacts->GetNumberOfVerts(), 2);
  vtkPointData* pd = contacts->GetPointData();
  for (vtkIdType i = 0; i < 2; ++i) {
    const auto& c = expected[static_cast<std::size_t>(i)];
    double p[3];
    contacts->GetPoint(i, p);
    EXPECT_EQ(std::vector<double>(p, p + 3), components(c.position));
    EXPECT_EQ(tuple(pd->GetArray("force"), i), components(c.force));
    EXPECT_EQ(pd->GetArray("normal_force")->GetTuple1(i), c.normalForce);
    EXPECT_EQ(pd->GetArray("force_magnitude")->GetTuple1(i), c.force.norm());
    EXPECT_EQ(pd->GetArray("body_a")->GetTuple1(i), c.bodyA);
    EXPECT_EQ(pd->GetArray("body_b")->GetTuple1(i), c.bodyB);
  }

  // Nothing half-written is left behind.
  for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(OutputFiles, VtkResumeKeepsFramesUpToTheRestartTime) {
  {
    VtkFrameWriter writer(vtkSettings(dir_, true));
    writeFrames(writer, motion_, 0, kFrames);
  }
  // Restart from a checkpoint at the time of the third frame (k = 2): frames 0-2 stay, 3-4 go.
  VtkFrameWriter resumed(vtkSettings(dir_, true, frameTime(2)));
  EXPECT_EQ(resumed.frameCount(), 3u);
  EXPECT_EQ(collectionByVtk(dir_ / "bodies.pvd").size(), 3u);
  EXPECT_EQ(collectionByVtk(dir_ / "contacts.pvd").size(), 3u);
  EXPECT_FALSE(fs::exists(dir_ / "bodies" / "frame_000003.vtp"));
  EXPECT_FALSE(fs::exists(dir_ / "contacts" / "frame_000004.vtp"));
  EXPECT_TRUE(fs::exists(dir_ / "bodies" / "frame_000002.vtp"));

  // The resumed run writes frames 3 and 4 again (here with the same motion): numbering goes on
  // and the displacement is still measured from frame 0, whose position the writer read back.
  writeFrames(resumed, motion_, 3, kFrames);
  const auto listed = collectionByVtk(dir_ / "bodies.pvd");
  ASSERT_EQ(listed.size(), static_cast<std::size_t>(kFrames));
  for (int k = 0; k < kFrames; ++k) {
    EXPECT_EQ(listed[static_cast<std::size_t>(k)].first, frameTime(k));
    EXPECT_EQ(listed[static_cast<std::size_t>(k)].second, fmt::format("bodies/frame_{:06d}.vtp", k));
  }
  expectBodiesFrame(dir_ / "bodies" / "frame_000004.vtp", motion_, 4);

  // A restart time between frames keeps those before it.
  VtkFrameWriter between(vtkSettings(dir_, false, 0.5 * (frameTime(0) + frameTime(1))));
  EXPECT_EQ(between.frameCount(), 1u);
  EXPECT_THROW(between.write(motion_.frame(0)), std::logic_error); // time does not advance
  between.write(motion_.frame(1));
  EXPECT_EQ(collectionByVtk(dir_ / "bodies.pvd").size(), 2u);
  // contacts were switched off on this resume: no stale contact collection stays behind.
  EXPECT_FALSE(fs::exists(dir_ / "contacts.pvd"));
}

TEST_F(OutputFiles, VtkFreshStartClearsAnEarlierRun) {
  {
    VtkFrameWriter writer(vtkSettings(dir_));
    writeFrames(writer, motion_, 0, kFrames);
  }
  VtkFrameWriter fresh(vtkSettings(dir_));
  EXPECT_FALSE(fs::exists(dir_ / "bodies.pvd"));
  EXPECT_FALSE(fs::exists(dir_ / "bodies" / "frame_000000.vtp"));
  fresh.write(motion_.frame(0));
  EXPECT_EQ(collectionByVtk(dir_ / "bodies.pvd").size(), 1u);
}

TEST_F(OutputFiles, VtkFixedBodiesAreWrittenOnceBesideTheFrames) {
  // Two fixed bodies (an underlayer's rocks) beside the three moving cubes: the frames hold the
  // moving ones only, fixed_bodies.vtp the fixed ones at their exact world vertices, written at the
  // first frame and not again while the fixed set stays the same; a changed set rewrites it, and a
  // fresh writer removes an earlier run's.
  const auto withFixed = [&](int k, int fixedCount) {
    BodyFrame f = motion_.frame(k);
    for (int i = 0; i < fixedCount; ++i) {
      BodySnapshot b;
      b.id = 20 + i;
      b.position = Vec3(-4.0 + 2.5 * i, 1.25, -0.5);
      b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7 + i, Vec3(0.0, 1.0, 1.0).normalized()));
      b.surface = &motion_.cube();
      b.scale = 1.5;
      b.fixed = true;
      f.bodies.push_back(b);
    }
    return f;
  };
  const fs::path fixedFile = dir_ / "fixed_bodies.vtp";
  {
    VtkFrameWriter writer(vtkSettings(dir_));
    writer.write(withFixed(0, 2));
    ASSERT_TRUE(fs::is_regular_file(fixedFile));
    auto fixed = readPolyData(fixedFile);
    const auto nv = static_cast<vtkIdType>(motion_.cube().vertexCount());
    ASSERT_EQ(fixed->GetNumberOfPoints(), 2 * nv);
    EXPECT_EQ(fixed->GetNumberOfPolys(), 2 * static_cast<vtkIdType>(motion_.cube().triangleCount()));
    const BodyFrame f = withFixed(0, 2);
    for (int i = 0; i < 2; ++i) {
      const BodySnapshot& b = f.bodies[static_cast<std::size_t>(kBodies + i)];
      for (vtkIdType v = 0; v < nv; v += 3) {
        double p[3];
        fixed->GetPoint(i * nv + v, p);
        const Vec3 expected = b.position + b.orientation.toRotationMatrix() * (b.scale * motion_.cube().vertices[v]);
        EXPECT_EQ(std::vector<double>(p, p + 3), components(expected));
        EXPECT_EQ(fixed->GetPointData()->GetArray("body_id")->GetTuple1(i * nv + v), b.id);
      }
    }
    EXPECT_EQ(fixed->GetPointData()->GetArray("displacement"), nullptr) << "no motion arrays for fixed bodies";
    expectBodiesFrame(dir_ / "bodies" / "frame_000000.vtp", motion_, 0); // the moving cubes only

    fs::remove(fixedFile);
    writer.write(withFixed(1, 2));
    EXPECT_FALSE(fs::exists(fixedFile)) << "the same fixed bodies are not written again";
    writer.write(withFixed(2, 1));
    ASSERT_TRUE(fs::is_regular_file(fixedFile)) << "a changed set of fixed bodies is written";
    EXPECT_EQ(readPolyData(fixedFile)->GetNumberOfPoints(), static_cast<vtkIdType>(motion_.cube().vertexCount()));
    expectBodiesFrame(dir_ / "bodies" / "frame_000002.vtp", motion_, 2);
  }
  VtkFrameWriter fresh(vtkSettings(dir_));
  EXPECT_FALSE(fs::exists(fixedFile)) << "a fresh run removes an earlier run's fixed bodies";
}

TEST_F(OutputFiles, VtkUnwritableFolderNamesThePath) {
  // A regular file where a folder should be: fails for root too, unlike a permission bit.
  std::ofstream(dir_ / "file") << "x";
  const fs::path folder = dir_ / "file" / "out";
  const auto message = inputErrorFrom([&] { VtkFrameWriter writer(vtkSettings(folder)); });
  EXPECT_NE(message.find(folder.string()), std::string::npos) << message;
}

// ---------------------------------------------------------------------------------------------
// netCDF body series
// ---------------------------------------------------------------------------------------------

namespace {

/// Read-only access to a netCDF file; every call is asserted.
class NcReader {
public:
  explicit NcReader(const fs::path& path) { EXPECT_EQ(nc_open(path.c_str(), NC_NOWRITE, &id_), NC_NOERR) << path; }
  ~NcReader() {
    if (id_ >= 0) {
      nc_close(id_);
    }
  }
  NcReader(const NcReader&) = delete;
  NcReader& operator=(const NcReader&) = delete;
  [[nodiscard]] bool ok() const { return id_ >= 0; }

  std::size_t dim(const char* name) const {
    int d = -1;
    std::size_t n = 0;
    EXPECT_EQ(nc_inq_dimid(id_, name, &d), NC_NOERR) << name;
    EXPECT_EQ(nc_inq_dimlen(id_, d, &n), NC_NOERR) << name;
    return n;
  }
  int var(const char* name) const {
    int v = -1;
    EXPECT_EQ(nc_inq_varid(id_, name, &v), NC_NOERR) << name;
    return v;
  }
  std::string text(const char* variable, const char* attribute) const {
    const int v = variable == nullptr ? NC_GLOBAL : var(variable);
    std::size_t n = 0;
    if (nc_inq_attlen(id_, v, attribute, &n) != NC_NOERR) {
      return "<missing>";
    }
    std::string s(n, '\0');
    EXPECT_EQ(nc_get_att_text(id_, v, attribute, s.data()), NC_NOERR);
    return s;
  }
  std::vector<double> doubles(const char* name) const {
    const int v = var(name);
    std::size_t n = 1;
    int ndims = 0;
    int dims[NC_MAX_VAR_DIMS];
    nc_inq_varndims(id_, v, &ndims);
    nc_inq_vardimid(id_, v, dims);
    for (int d = 0; d < ndims; ++d) {
      std::size_t len = 0;
      nc_inq_dimlen(id_, dims[d], &len);
      n *= len;
    }
    std::vector<double> out(n);
    EXPECT_EQ(nc_get_var_double(id_, v, out.data()), NC_NOERR) << name;
    return out;
  }
  [[nodiscard]] int id() const { return id_; }

private:
  int id_ = -1;
};

/// Expect the records of `file` to equal motion frames `frames` (record r = frame frames[r]).
void expectRecords(const NcReader& nc, const Motion& motion, const std::vector<int>& frames) {
  const auto time = nc.doubles("time");
  const auto position = nc.doubles("position");
  const auto orientation = nc.doubles("orientation");
  const auto velocity = nc.doubles("velocity");
  const auto angular = nc.doubles("angular_velocity");
  const auto count = nc.doubles("contact_count");
  const auto force = nc.doubles("max_contact_force");
  ASSERT_EQ(time.size(), frames.size());
  for (std::size_t r = 0; r < frames.size(); ++r) {
    const BodyFrame f = motion.frame(frames[r]);
    // float64 stored, shuffle + zlib lossless: bit-for-bit equality.
    EXPECT_EQ(time[r], f.time);
    for (std::size_t i = 0; i < kBodies; ++i) {
      const auto& b = f.bodies[i];
      const std::size_t v = (r * kBodies + i) * 3;
      const std::size_t q = (r * kBodies + i) * 4;
      EXPECT_EQ(std::vector<double>(position.begin() + v, position.begin() + v + 3), components(b.position));
      EXPECT_EQ(std::vector<double>(velocity.begin() + v, velocity.begin() + v + 3), components(b.velocity));
      EXPECT_EQ(std::vector<double>(angular.begin() + v, angular.begin() + v + 3), components(b.angularVelocity));
      EXPECT_EQ(std::vector<double>(orientation.begin() + q, orientation.begin() + q + 4),
                (std::vector<double>{b.orientation.w(), b.orientation.x(), b.orientation.y(), b.orientation.z()}));
      EXPECT_EQ(count[r * kBodies + i], b.contactCount);
      EXPECT_EQ(force[r * kBodies + i], b.maxContactForce);
    }
  }
  for (std::size_t r = 1; r < time.size(); ++r) {
    EXPECT_GT(time[r], time[r - 1]) << "time must increase";
  }
}

} // namespace

TEST_F(OutputFiles, SeriesFileHasCfLayoutAndExactValues) {
  const fs::path path = dir_ / "series" / "bodies.nc"; // the folder is created
  {
    BodySeriesFile series(seriesSettings(path, "armour run pile.yaml"), Motion::table());
    for (int k = 0; k < kFrames; ++k) {
      series.append(motion_.frame(k));
    }
    EXPECT_THROW(series.append(motion_.frame(kFrames - 1)), std::logic_error); // time must advance
    auto shuffled = motion_.frame(kFrames);
    std::swap(shuffled.bodies[0], shuffled.bodies[1]);
    EXPECT_THROW(series.append(shuffled), std::logic_error); // bodies in another order
    EXPECT_EQ(series.recordCount(), static_cast<std::size_t>(kFrames));
  }
  NcReader nc(path);
  ASSERT_TRUE(nc.ok());
  int format = 0;
  nc_inq_format(nc.id(), &format);
  EXPECT_EQ(format, NC_FORMAT_NETCDF4);
  EXPECT_EQ(nc.dim("time"), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(nc.dim("body"), static_cast<std::size_t>(kBodies));
  EXPECT_EQ(nc.dim("vec"), 3u);
  EXPECT_EQ(nc.dim("quat"), 4u);
  EXPECT_EQ(nc.dim("name_strlen"), std::string("unit_long_name_1").size());
  int unlimited = -1;
  nc_inq_unlimdim(nc.id(), &unlimited);
  int timeDim = -1;
  nc_inq_dimid(nc.id(), "time", &timeDim);
  EXPECT_EQ(unlimited, timeDim);

  EXPECT_EQ(nc.text(nullptr, "Conventions"), "CF-1.8");
  EXPECT_EQ(nc.text(nullptr, "source").rfind("armour ", 0), 0u);
  EXPECT_NE(nc.text(nullptr, "history").find("armour run pile.yaml"), std::string::npos);
  EXPECT_EQ(nc.text("time", "units"), "s");
  EXPECT_EQ(nc.text("time", "standard_name"), "time");
  EXPECT_EQ(nc.text("time", "axis"), "T");
  EXPECT_EQ(nc.text("position", "units"), "m");
  EXPECT_EQ(nc.text("position", "long_name"), "centre of mass position");
  EXPECT_EQ(nc.text("orientation", "units"), "1");
  EXPECT_EQ(nc.text("velocity", "units"), "m s-1");
  EXPECT_EQ(nc.text("angular_velocity", "units"), "rad s-1");
  EXPECT_EQ(nc.text("contact_count", "units"), "1");
  EXPECT_EQ(nc.text("max_contact_force", "units"), "N");
  EXPECT_EQ(nc.text("position", "coordinates"), "body_name");
  EXPECT_NE(nc.text("velocity", "comment").find("x onshore"), std::string::npos);

  // Names as fixed-width char rows, NUL padded.
  std::vector<char> names(kBodies * nc.dim("name_strlen"));
  ASSERT_EQ(nc_get_var_text(nc.id(), nc.var("body_name"), names.data()), NC_NOERR);
  const auto table = Motion::table();
  for (std::size_t i = 0; i < kBodies; ++i) {
    const char* row = names.data() + i * nc.dim("name_strlen");
    EXPECT_EQ(std::string(row, strnlen(row, nc.dim("name_strlen"))), table[i].name);
  }
  EXPECT_EQ(nc.doubles("body_id"), (std::vector<double>{10, 11, 12}));

  // Chunked along time, deflated with shuffle.
  int storage = -1;
  std::size_t chunks[3] = {};
  ASSERT_EQ(nc_inq_var_chunking(nc.id(), nc.var("position"), &storage, chunks), NC_NOERR);
  EXPECT_EQ(storage, NC_CHUNKED);
  EXPECT_EQ(chunks[0], 64u);
  EXPECT_EQ(chunks[1], static_cast<std::size_t>(kBodies));
  EXPECT_EQ(chunks[2], 3u);
  int shuffle = 0, deflate = 0, level = 0;
  ASSERT_EQ(nc_inq_var_deflate(nc.id(), nc.var("velocity"), &shuffle, &deflate, &level), NC_NOERR);
  EXPECT_EQ(shuffle, 1);
  EXPECT_EQ(deflate, 1);
  EXPECT_EQ(level, 2);

  expectRecords(nc, motion_, {0, 1, 2, 3, 4});
  EXPECT_FALSE(fs::exists(armour::core::temporarySibling(path))) << "temporary left behind";
}

TEST_F(OutputFiles, SeriesResumeKeepsRecordsUpToTheRestartTime) {
  const fs::path path = dir_ / "bodies.nc";
  {
    BodySeriesFile series(seriesSettings(path, "armour run pile.yaml"), Motion::table());
    for (int k = 0; k < kFrames; ++k) {
      series.append(motion_.frame(k));
    }
  }
  {
    BodySeriesFile resumed(seriesSettings(path, "armour run pile.yaml --resume", frameTime(2)),
                           Motion::table());
    EXPECT_EQ(resumed.recordCount(), 3u);
    EXPECT_THROW(resumed.append(motion_.frame(2)), std::logic_error); // already in the file
    // The continued run differs from the abandoned one (frames 5 and 6 at the times of 3 and 4).
    resumed.append(motion_.frame(5, frameTime(3)));
    resumed.append(motion_.frame(6, frameTime(4)));
  }
  NcReader nc(path);
  ASSERT_TRUE(nc.ok());
  const auto time = nc.doubles("time");
  ASSERT_EQ(time.size(), 5u);
  EXPECT_EQ(time[3], frameTime(3));
  // Values: frames 0-2 from the first run, then 5 and 6 (whose own times were overridden).
  const auto position = nc.doubles("position");
  EXPECT_EQ(std::vector<double>(position.begin(), position.begin() + 3), components(Motion::position(0, 0)));
  EXPECT_EQ(std::vector<double>(position.begin() + 3 * 3 * 3, position.begin() + 3 * 3 * 3 + 3),
            components(Motion::position(0, 5)));
  EXPECT_EQ(std::vector<double>(position.begin() + 4 * 3 * 3 + 6, position.begin() + 4 * 3 * 3 + 9),
            components(Motion::position(2, 6)));
  const auto history = nc.text(nullptr, "history");
  EXPECT_NE(history.find("armour run pile.yaml\n"), std::string::npos) << history;
  EXPECT_NE(history.find("--resume (resumed at t = 0.25 s)"), std::string::npos) << history;
}

TEST_F(OutputFiles, SeriesResumeRefusesAnotherScene) {
  const fs::path path = dir_ / "bodies.nc";
  {
    BodySeriesFile series(seriesSettings(path), Motion::table());
    series.append(motion_.frame(0));
  }
  auto other = Motion::table();
  other[1].name = "renamed";
  const auto message = inputErrorFrom([&] { BodySeriesFile s(seriesSettings(path, "", 1.0), other); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  EXPECT_NE(message.find("renamed"), std::string::npos) << message;
  // The refused resume left the file as it was.
  NcReader nc(path);
  EXPECT_EQ(nc.dim("time"), 1u);
}

TEST_F(OutputFiles, SeriesSurvivesAKillAfterAFlush) {
  const fs::path path = dir_ / "bodies.nc";
  // The child writes 5 records flushing every 2 and is killed without closing the file: records
  // 0-3 were flushed and must be readable; record 4 may or may not be there.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      auto* series = new BodySeriesFile(seriesSettings(path, "", {}, 2), Motion::table()); // never closed
      for (int k = 0; k < kFrames; ++k) {
        series->append(motion_.frame(k));
      }
    } catch (...) {
      ::_exit(3);
    }
    ::kill(::getpid(), SIGKILL);
    ::_exit(4);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "child status " << status;
  NcReader nc(path);
  ASSERT_TRUE(nc.ok());
  const std::size_t records = nc.dim("time");
  EXPECT_GE(records, 4u);
  expectRecords(nc, motion_, records >= 5 ? std::vector<int>{0, 1, 2, 3, 4} : std::vector<int>{0, 1, 2, 3});
}

TEST_F(OutputFiles, SeriesIsReadableWhileTheRunGoesOn) {
  // Between flushes the file is closed and whole: another program opens it and finds every
  // flushed record, and none of the staged ones. (Open for writing, an HDF5 file is neither
  // readable by others nor safe from a kill: issue 22's cli_restart lost bodies.nc once in 40.)
  const fs::path path = dir_ / "bodies.nc";
  BodySeriesFile series(seriesSettings(path, "", {}, 2), Motion::table());
  for (int k = 0; k < 3; ++k) {
    series.append(motion_.frame(k));
  }
  {
    NcReader nc(path);
    ASSERT_TRUE(nc.ok());
    EXPECT_EQ(nc.dim("time"), 2u);
    expectRecords(nc, motion_, {0, 1});
  }
  series.flush();
  {
    NcReader nc(path);
    ASSERT_TRUE(nc.ok());
    EXPECT_EQ(nc.dim("time"), 3u);
    expectRecords(nc, motion_, {0, 1, 2});
  }
  // A reader in another process holds the file open (with HDF5's lock, as ncdump or Python
  // would) while the next block is written: the run goes on.
  int toChild[2], toParent[2];
  ASSERT_EQ(::pipe(toChild), 0);
  ASSERT_EQ(::pipe(toParent), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::setenv("HDF5_USE_FILE_LOCKING", "TRUE", 1);
    int id = -1;
    char c = nc_open(path.c_str(), NC_NOWRITE, &id) == NC_NOERR ? 'o' : 'x';
    (void)!::write(toParent[1], &c, 1);
    (void)!::read(toChild[0], &c, 1);
    if (id >= 0) nc_close(id);
    ::_exit(0);
  }
  char opened = 0;
  ASSERT_EQ(::read(toParent[0], &opened, 1), 1);
  EXPECT_EQ(opened, 'o') << "the reader could not open the file between blocks";
  series.append(motion_.frame(3));
  EXPECT_NO_THROW(series.append(motion_.frame(4))) << "a block could not be written while a reader held the file";
  char go = 'g';
  (void)!::write(toChild[1], &go, 1);
  int status = 0;
  ::waitpid(child, &status, 0);
  for (int fd : {toChild[0], toChild[1], toParent[0], toParent[1]}) ::close(fd);
  series.close();
  NcReader nc(path);
  expectRecords(nc, motion_, {0, 1, 2, 3, 4});
}

TEST_F(OutputFiles, SeriesWrittenInBlocksIsAsSmallAsInOneGo) {
  // Chunks are whole per flush (records per chunk a multiple or divisor of the block): no chunk
  // is rewritten by a reopened file, which would leave its old copy as dead space. 96 records in
  // 24 blocks of 4 against one block of 96, both in chunks of 4 records: sizes within 2 %.
  const auto write = [&](const fs::path& path, std::size_t block) {
    BodySeriesSettings s = seriesSettings(path, "", {}, block);
    s.chunkRecords = 4;
    BodySeriesFile series(s, Motion::table());
    for (int k = 0; k < 96; ++k) {
      series.append(motion_.frame(k % kFrames, 0.01 * (k + 1)));
    }
    series.close();
    return static_cast<double>(fs::file_size(path));
  };
  const double blocks = write(dir_ / "blocks.nc", 4);
  const double once = write(dir_ / "once.nc", 96);
  EXPECT_LT(blocks, 1.02 * once) << "blocks of 4: " << blocks << " bytes, one block: " << once << " bytes";
}

TEST_F(OutputFiles, SeriesResumeRefusesADamagedFileNamingTheFix) {
  // A file whose records cannot be read (here: a compressed chunk overwritten, as a kill inside a
  // flush can leave it) is refused on resume with the first bad record and the fix, not with a
  // bare "HDF error", and is left as it was.
  const fs::path path = dir_ / "bodies.nc";
  {
    BodySeriesSettings s = seriesSettings(path, "", {}, 96);
    BodySeriesFile series(s, Motion::table());
    for (int k = 0; k < 96; ++k) {
      series.append(motion_.frame(k % kFrames, 0.01 * (k + 1)));
    }
  }
  const auto size = fs::file_size(path);
  {
    // Overwrite the middle third of the file (raw chunks; the header and the index are at its ends).
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 3));
    const std::string junk(size / 3, '\x5a');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  const auto before = fs::file_size(path);
  const auto message = inputErrorFrom([&] { BodySeriesFile s(seriesSettings(path, "", 0.5), Motion::table()); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  const bool named = message.find("is damaged: its variable '") != std::string::npos &&
                     message.find("cannot be read from record") != std::string::npos &&
                     message.find("mv ") != std::string::npos;
  // The reader's probe may refuse the file first, with its own fix.
  const bool probed = message.find("move it away") != std::string::npos || message.find("damaged") != std::string::npos;
  EXPECT_TRUE(named || probed) << message;
  EXPECT_EQ(fs::file_size(path), before);
}

TEST_F(OutputFiles, SeriesUnwritableFolderNamesThePath) {
  std::ofstream(dir_ / "file") << "x";
  const fs::path path = dir_ / "file" / "bodies.nc";
  const auto message = inputErrorFrom([&] { BodySeriesFile s(seriesSettings(path), Motion::table()); });
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
  // A folder that exists but where netCDF cannot create the file: the path is a folder.
  fs::create_directories(dir_ / "taken.nc" / "x");
  const auto message2 = inputErrorFrom([&] {
    BodySeriesFile s(seriesSettings(dir_ / "taken.nc"), Motion::table());
  });
  EXPECT_NE(message2.find("taken.nc"), std::string::npos) << message2;
}
