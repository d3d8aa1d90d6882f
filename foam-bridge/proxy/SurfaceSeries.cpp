// SPDX-License-Identifier: GPL-3.0-or-later
#include "proxy/SurfaceSeries.hpp"

#include "core/Error.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <fstream>

namespace armour::proxy {

namespace fs = std::filesystem;

const std::vector<double>& Surface::field(const std::string& name, int expectedComponents) const {
  const auto it = fields.find(name);
  if (it == fields.end()) {
    std::string present;
    for (const auto& [n, v] : fields) present += (present.empty() ? "" : ", ") + n;
    core::failInput(source, "no field '{}' (fields: {}); add it to the `fields` of the surfaces function object or "
                            "name the right one (--p-field, --u-field, --alpha-field)", name, present);
  }
  if (components.at(name) != expectedComponents) {
    core::failInput(source, "field '{}' has {} components; expected {}", name, components.at(name), expectedComponents);
  }
  return it->second;
}

void Surface::bounds(std::size_t f, double& xLo, double& xHi, double& yLo, double& yHi, double& zLo,
                     double& zHi) const {
  xLo = yLo = zLo = INFINITY;
  xHi = yHi = zHi = -INFINITY;
  for (long k = offsets[f]; k < offsets[f + 1]; ++k) {
    const double* p = &points[3 * static_cast<std::size_t>(connectivity[static_cast<std::size_t>(k)])];
    xLo = std::min(xLo, p[0]);
    xHi = std::max(xHi, p[0]);
    yLo = std::min(yLo, p[1]);
    yHi = std::max(yHi, p[1]);
    zLo = std::min(zLo, p[2]);
    zHi = std::max(zHi, p[2]);
  }
}

bool Surface::containsXZ(std::size_t f, double x, double z) const {
  // Crossing number of the polygon projected on x-z (a cutting plane y = const lies in x-z).
  bool inside = false;
  const long n = offsets[f + 1] - offsets[f];
  for (long i = 0, j = n - 1; i < n; j = i++) {
    const double* a = &points[3 * static_cast<std::size_t>(connectivity[static_cast<std::size_t>(offsets[f] + i)])];
    const double* b = &points[3 * static_cast<std::size_t>(connectivity[static_cast<std::size_t>(offsets[f] + j)])];
    if ((a[2] > z) != (b[2] > z) && x < (b[0] - a[0]) * (z - a[2]) / (b[2] - a[2]) + a[0]) inside = !inside;
  }
  return inside;
}

namespace {

/// OpenFOAM's face centre and area (primitiveMesh::makeFaceCentresAndAreas): triangles directly,
/// other polygons as triangles about the point average, area-weighted. The same rule as the mesh,
/// so a face lands in the same voxel as in the function object.
void faceGeometry(Surface& s) {
  const std::size_t nf = s.offsets.size() - 1;
  s.centreX.resize(nf);
  s.centreY.resize(nf);
  s.centreZ.resize(nf);
  s.areaX.resize(nf);
  s.areaY.resize(nf);
  s.areaZ.resize(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const long n = s.offsets[f + 1] - s.offsets[f];
    auto pt = [&](long i) { return &s.points[3 * static_cast<std::size_t>(s.connectivity[static_cast<std::size_t>(s.offsets[f] + i)])]; };
    double c[3] = {0, 0, 0}, area[3] = {0, 0, 0};
    if (n == 3) {
      const double *a = pt(0), *b = pt(1), *d = pt(2);
      for (int k = 0; k < 3; ++k) c[k] = (1.0 / 3.0) * (a[k] + b[k] + d[k]);
      const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
      area[0] = 0.5 * (e1[1] * e2[2] - e1[2] * e2[1]);
      area[1] = 0.5 * (e1[2] * e2[0] - e1[0] * e2[2]);
      area[2] = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]);
    } else if (n > 3) {
      double m[3] = {0, 0, 0};
      for (long i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) m[k] += pt(i)[k];
      for (double& v : m) v /= static_cast<double>(n);
      double sumA = 0.0, sumAc[3] = {0, 0, 0}, sumN[3] = {0, 0, 0};
      for (long i = 0; i < n; ++i) {
        const double* p = pt(i);
        const double* q = pt(i + 1 == n ? 0 : i + 1);
        const double e1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        const double e2[3] = {m[0] - p[0], m[1] - p[1], m[2] - p[2]};
        const double nn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const double a = std::sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        for (int k = 0; k < 3; ++k) {
          sumN[k] += nn[k];
          sumAc[k] += a * (p[k] + q[k] + m[k]);
        }
        sumA += a;
      }
      for (int k = 0; k < 3; ++k) {
        c[k] = sumA < 1e-150 ? m[k] : (1.0 / 3.0) * sumAc[k] / sumA;
        area[k] = 0.5 * sumN[k];
      }
    }
    s.centreX[f] = c[0];
    s.centreY[f] = c[1];
    s.centreZ[f] = c[2];
    s.areaX[f] = area[0];
    s.areaY[f] = area[1];
    s.areaZ[f] = area[2];
  }
}

/// The numbers of a whitespace-separated text file (the `sets` raw output, the `surfaces` raw
/// output): '#' lines are comments, every other non-empty line a row of numbers. Parsed with
/// std::from_chars over the whole file in memory (an istringstream per line took 5 times the CPU
/// time on the smoke cases' sets output, docs/benchmarks.md).
struct TextTable {
  std::vector<std::string> comments;
  std::size_t columns = 0;
  std::vector<double> values; ///< row-major
  std::size_t rows() const { return columns == 0 ? 0 : values.size() / columns; }
  double at(std::size_t r, std::size_t c) const { return values[r * columns + c]; }
  /// Column c of every row (the x, y, z of the points are columns 0, 1, 2).
  std::vector<double> column(std::size_t c) const {
    std::vector<double> v(rows());
    for (std::size_t r = 0; r < v.size(); ++r) v[r] = at(r, c);
    return v;
  }
};

TextTable readTextTable(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) core::failInput(file.string(), "cannot open the file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  TextTable t;
  const char* p = text.data();
  const char* const end = p + text.size();
  std::size_t line = 0;
  while (p < end) {
    ++line;
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    if (!eol) eol = end;
    const char* q = p;
    while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
    if (q < eol && *q == '#') {
      t.comments.emplace_back(q, eol);
    } else if (q < eol) {
      std::size_t n = 0;
      while (q < eol) {
        double v = 0.0;
        const auto [next, ec] = std::from_chars(q, eol, v);
        if (ec != std::errc()) {
          core::failInput(file.string(), "line {}: '{}' is not a number", line,
                          std::string(q, std::min<const char*>(eol, q + 20)));
        }
        t.values.push_back(v);
        ++n;
        q = next;
        while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
      }
      if (t.columns == 0) t.columns = n;
      else if (n != t.columns) core::failInput(file.string(), "line {} has {} columns; expected {}", line, n, t.columns);
    }
    p = eol + 1;
  }
  return t;
}

} // namespace

Surface readSurface(const fs::path& file) {
  if (!fs::exists(file)) core::failInput(file.string(), "no such file; is the surfaces function object writing it?");
  vtkSmartPointer<vtkPolyData> poly;
  const std::string ext = file.extension().string();
  if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    if (reader->GetErrorCode() != 0) core::failInput(file.string(), "VTK could not read this XML poly data file");
    poly = reader->GetOutput();
  } else {
    vtkNew<vtkPolyDataReader> reader;
    reader->SetFileName(file.c_str());
    reader->ReadAllFieldsOn();
    reader->ReadAllScalarsOn();
    reader->ReadAllVectorsOn();
    reader->Update();
    if (reader->GetErrorCode() != 0 || !reader->IsFilePolyData())
      core::failInput(file.string(), "not a legacy VTK POLYDATA file that VTK can read");
    poly = reader->GetOutput();
  }
  if (!poly) core::failInput(file.string(), "VTK returned no data");
  Surface s;
  s.source = file.string();
  const vtkIdType np = poly->GetNumberOfPoints();
  s.points.resize(3 * static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) poly->GetPoint(i, &s.points[3 * static_cast<std::size_t>(i)]);
  vtkCellArray* polys = poly->GetPolys();
  const vtkIdType nf = polys ? polys->GetNumberOfCells() : 0;
  if (poly->GetNumberOfCells() != nf) {
    core::failInput(file.string(), "{} cells of which {} polygons: a sampled surface holds polygons only",
                    poly->GetNumberOfCells(), nf);
  }
  s.offsets.reserve(static_cast<std::size_t>(nf) + 1);
  s.offsets.push_back(0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType f = 0; f < nf; ++f) {
    polys->GetCellAtId(f, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) s.connectivity.push_back(static_cast<long>(ids->GetId(k)));
    s.offsets.push_back(static_cast<long>(s.connectivity.size()));
  }
  faceGeometry(s);
  vtkCellData* cd = poly->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a) {
    vtkDataArray* array = cd->GetArray(a);
    if (!array || !array->GetName()) continue;
    const int nc = array->GetNumberOfComponents();
    if (array->GetNumberOfTuples() != nf) continue;
    std::vector<double> values(static_cast<std::size_t>(nf) * static_cast<std::size_t>(nc));
    for (vtkIdType f = 0; f < nf; ++f)
      for (int c = 0; c < nc; ++c) values[static_cast<std::size_t>(f * nc + c)] = array->GetComponent(f, c);
    s.fields[array->GetName()] = std::move(values);
    s.components[array->GetName()] = nc;
  }
  return s;
}

const std::vector<double>& PointSet::field(const std::string& name, int expectedComponents) const {
  const auto it = fields.find(name);
  if (it == fields.end()) {
    std::string present;
    for (const auto& [n, v] : fields) present += (present.empty() ? "" : ", ") + n;
    core::failInput(source, "no field '{}' (fields: {}); add it to the `fields` of the sets function object",
                    name, present);
  }
  if (components.at(name) != expectedComponents) {
    core::failInput(source, "field '{}' has {} components; expected {}", name, components.at(name), expectedComponents);
  }
  return it->second;
}

PointSet readPointSet(const fs::path& timeFolder, const std::string& set, const std::vector<std::string>& fieldNames,
                      const std::vector<std::string>& needed) {
  PointSet out;
  out.source = (timeFolder / set).string();
  const std::string prefix = set + "_";
  bool any = false;
  std::vector<fs::path> files;
  if (fs::is_directory(timeFolder)) {
    for (const auto& e : fs::directory_iterator(timeFolder)) {
      const std::string name = e.path().filename().string();
      if (name.size() > prefix.size() + 3 && name.compare(0, prefix.size(), prefix) == 0 &&
          name.compare(name.size() - 3, 3, ".xy") == 0)
        files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    // Field names from the file name, longest known name first (p_rgh before p).
    const std::string name = file.filename().string();
    const std::string middle = name.substr(prefix.size(), name.size() - prefix.size() - 3);
    std::vector<std::string> tokens;
    for (std::size_t a = 0;;) {
      const std::size_t b = middle.find('_', a);
      tokens.push_back(middle.substr(a, b == std::string::npos ? std::string::npos : b - a));
      if (b == std::string::npos) break;
      a = b + 1;
    }
    std::vector<std::string> names;
    for (std::size_t i = 0; i < tokens.size();) {
      std::size_t take = 1;
      for (std::size_t j = tokens.size(); j > i + 1; --j) {
        std::string joined = tokens[i];
        for (std::size_t k = i + 1; k < j; ++k) joined += "_" + tokens[k];
        if (std::find(fieldNames.begin(), fieldNames.end(), joined) != fieldNames.end()) {
          take = j - i;
          break;
        }
      }
      std::string joined = tokens[i];
      for (std::size_t k = i + 1; k < i + take; ++k) joined += "_" + tokens[k];
      names.push_back(joined);
      i += take;
    }
    if (!needed.empty() && std::none_of(names.begin(), names.end(), [&needed](const std::string& n) {
          return std::find(needed.begin(), needed.end(), n) != needed.end();
        }))
      continue;
    const TextTable table = readTextTable(file);
    const std::size_t cols = table.rows() == 0 ? 3 + names.size() : table.columns;
    if (cols < 4 || (cols - 3) % names.size() != 0) {
      core::failInput(file.string(), "{} columns for the fields {}: expected x y z and then the fields (setFormat "
                                     "raw, axis xyz)", cols, middle);
    }
    const std::size_t rows = table.rows();
    const std::size_t nc = (cols - 3) / names.size();
    if (!any) {
      out.x = table.column(0);
      out.y = table.column(1);
      out.z = table.column(2);
    } else if (rows != out.x.size()) {
      core::failInput(file.string(), "{} points but {} in the other files of set '{}'", rows, out.x.size(), set);
    }
    for (std::size_t f = 0; f < names.size(); ++f) {
      std::vector<double> values(rows * nc);
      for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < nc; ++c) values[r * nc + c] = table.at(r, 3 + f * nc + c);
      out.fields[names[f]] = std::move(values);
      out.components[names[f]] = static_cast<int>(nc);
    }
    any = true;
  }
  if (!any && !files.empty()) {
    std::string wanted;
    for (const std::string& n : needed) wanted += (wanted.empty() ? "" : ", ") + n;
    core::failInput(out.source, "no {}*.xy file holds {}: add it to the `fields` of the sets function object",
                    prefix, wanted);
  }
  if (!any) {
    core::failInput(out.source, "no {}*.xy files: the sets function object (setFormat raw) has no set named '{}' at "
                                "this time", prefix, set);
  }
  return out;
}

Surface readRawSurface(const fs::path& timeFolder, const std::string& surface, const std::vector<std::string>& fieldNames) {
  Surface s;
  s.source = (timeFolder / surface).string() + " (raw)";
  bool any = false;
  for (const std::string& field : fieldNames) {
    const fs::path file = timeFolder / (field + "_" + surface + ".raw");
    if (!fs::exists(file)) continue;
    const TextTable table = readTextTable(file);
    // "# <field>  FACE_DATA <n>": point data would be values at the points, not on the faces.
    std::size_t declared = table.rows();
    if (!table.comments.empty()) {
      const std::string& head = table.comments.front();
      if (head.find("POINT_DATA") != std::string::npos) {
        core::failInput(file.string(), "holds point data: sample the surface with `interpolate false` (face values)");
      }
      const std::size_t at = head.find("FACE_DATA");
      if (at != std::string::npos) declared = std::strtoul(head.c_str() + at + 9, nullptr, 10);
    }
    if (declared != table.rows()) {
      core::failInput(file.string(), "{} faces listed but the header says {}: the file is truncated", table.rows(), declared);
    }
    if (table.rows() > 0 && table.columns < 4) {
      core::failInput(file.string(), "{} columns: expected x y z and the value(s) of {}", table.columns, field);
    }
    const std::size_t rows = table.rows(), nc = table.rows() > 0 ? table.columns - 3 : 1;
    if (!any) {
      s.centreX = table.column(0);
      s.centreY = table.column(1);
      s.centreZ = table.column(2);
    } else {
      if (rows != s.faces()) {
        core::failInput(file.string(), "{} faces but {} in the other fields of surface '{}'", rows, s.faces(), surface);
      }
      for (std::size_t r = 0; r < rows; ++r) {
        if (table.at(r, 0) != s.centreX[r] || table.at(r, 1) != s.centreY[r] || table.at(r, 2) != s.centreZ[r]) {
          core::failInput(file.string(), "face {} is at ({}, {}, {}) m but at ({}, {}, {}) m in the other fields of "
                          "surface '{}'", r, table.at(r, 0), table.at(r, 1), table.at(r, 2), s.centreX[r],
                          s.centreY[r], s.centreZ[r], surface);
        }
      }
    }
    std::vector<double> values(rows * nc);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < nc; ++c) values[r * nc + c] = table.at(r, 3 + c);
    s.fields[field] = std::move(values);
    s.components[field] = static_cast<int>(nc);
    any = true;
  }
  if (!any) {
    core::failInput(s.source, "no <field>_{}.raw file for any of the fields: the surfaces function object "
                              "(surfaceFormat raw) has no surface named '{}' at this time", surface, surface);
  }
  return s;
}

Surface readSurfaceIn(const fs::path& timeFolder, const std::string& surface, const std::vector<std::string>& fieldNames) {
  for (const std::string& field : fieldNames) {
    if (fs::exists(timeFolder / (field + "_" + surface + ".raw"))) return readRawSurface(timeFolder, surface, fieldNames);
  }
  for (const char* ext : {".vtk", ".vtp"}) {
    const fs::path p = timeFolder / (surface + ext);
    if (fs::exists(p)) return readSurface(p);
  }
  core::failInput(timeFolder.string(), "no <field>_{}.raw, {}.vtk or {}.vtp: the surfaces function object has no "
                                       "surface named '{}' (or a different surface name was given)", surface,
                  surface, surface, surface);
}

std::vector<SampleTime> listSampleTimes(const fs::path& functionFolder) {
  if (!fs::is_directory(functionFolder)) {
    core::failInput(functionFolder.string(), "no such folder: run the case with the surfaces function object "
                                             "(foam-bridge/dictionaries/armourSurfaces) or give --function");
  }
  std::vector<SampleTime> times;
  for (const auto& entry : fs::directory_iterator(functionFolder)) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename().string();
    double t = 0.0;
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), t);
    if (ec != std::errc() || end != name.data() + name.size() || !std::isfinite(t)) continue;
    times.push_back({t, entry.path()});
  }
  std::sort(times.begin(), times.end(), [](const SampleTime& a, const SampleTime& b) { return a.time < b.time; });
  return times;
}

fs::path surfaceFile(const fs::path& timeFolder, const std::string& surface) {
  for (const char* ext : {".vtk", ".vtp"}) {
    const fs::path p = timeFolder / (surface + ext);
    if (fs::exists(p)) return p;
  }
  core::failInput(timeFolder.string(), "no {}.vtk or {}.vtp: the surfaces function object has no surface named '{}' "
                                       "(or a different surface name was given)", surface, surface, surface);
}

} // namespace armour::proxy
