// SPDX-License-Identifier: GPL-3.0-or-later
#include "deformable/DeformableVtu.hpp"

#include "deformable/StressFields.hpp"
#include "geometry/VtkSupport.hpp"

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <string>

namespace armour::deformable {
namespace {

vtkSmartPointer<vtkDoubleArray> vectorArray(const char* name, const std::vector<Vec3>& values) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) {
    array->SetTuple(static_cast<vtkIdType>(i), values[i].data());
  }
  return array;
}

/// The stress fields of `stress` as arrays added to `data` (point or cell data).
void addStressArrays(vtkDataSetAttributes& data, const std::vector<Mat3>& stress) {
  const auto count = static_cast<vtkIdType>(stress.size());
  vtkNew<vtkDoubleArray> tensor;
  tensor->SetName("cauchy_stress");
  tensor->SetNumberOfComponents(9);
  tensor->SetNumberOfTuples(count);
  const char* names[5] = {"sigma_1", "sigma_2", "sigma_3", "differential_stress", "von_mises"};
  vtkNew<vtkDoubleArray> scalars[5];
  for (int k = 0; k < 5; ++k) {
    scalars[k]->SetName(names[k]);
    scalars[k]->SetNumberOfTuples(count);
  }
  for (vtkIdType i = 0; i < count; ++i) {
    const Mat3& s = stress[static_cast<std::size_t>(i)];
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> rowMajor = s;
    tensor->SetTuple(i, rowMajor.data());
    const auto summary = summarizeStress(s);
    const double values[5] = {summary.principal[0], summary.principal[1], summary.principal[2], summary.differential,
                              summary.vonMises};
    for (int k = 0; k < 5; ++k) {
      scalars[k]->SetValue(i, values[k]);
    }
  }
  data.AddArray(tensor);
  for (auto& array : scalars) {
    data.AddArray(array);
  }
}

} // namespace

void writeDeformableVtu(const DeformableBody& body, const std::filesystem::path& path) {
  const auto& mesh = body.mesh();
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(geometry::toVtkPoints(body.positions()));
  const int nen = mesh.nodesPerElement();
  const int cellType = mesh.order == ElementOrder::Linear ? VTK_TETRA : VTK_QUADRATIC_TETRA;
  grid->Allocate(static_cast<vtkIdType>(mesh.elementCount()));
  for (std::size_t e = 0; e < mesh.elementCount(); ++e) {
    vtkIdType ids[10];
    for (int a = 0; a < nen; ++a) {
      ids[a] = mesh.element(e)[a];
    }
    grid->InsertNextCell(cellType, nen, ids);
  }
  std::vector<Vec3> displacement(mesh.nodeCount());
  for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
    displacement[n] = body.positions()[n] - mesh.nodes[n];
  }
  grid->GetPointData()->AddArray(vectorArray("displacement", displacement));
  grid->GetPointData()->AddArray(vectorArray("velocity", body.velocities()));
  const auto elementStress = body.elementStresses();
  std::vector<double> volumes(mesh.elementCount());
  for (std::size_t e = 0; e < volumes.size(); ++e) {
    volumes[e] = body.geometry()[e].volume;
  }
  addStressArrays(*grid->GetCellData(), elementStress);
  addStressArrays(*grid->GetPointData(), nodalStresses(mesh, elementStress, volumes));
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  geometry::writeVtkXmlAtomically(*writer, grid, path);
}

} // namespace armour::deformable
