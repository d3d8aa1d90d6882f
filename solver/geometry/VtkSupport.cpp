// SPDX-License-Identifier: GPL-3.0-or-later
#include "geometry/VtkSupport.hpp"

#include "core/AtomicFile.hpp"
#include "core/Error.hpp"

#include <vtkDataObject.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPoints.h>
#include <vtkXMLWriter.h>

namespace armour::geometry {
namespace {

/// Output window that keeps VTK's messages (first line of each) instead of printing them.
class CapturingOutputWindow : public vtkOutputWindow {
public:
  static CapturingOutputWindow* New();
  vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow)
  void DisplayText(const char* text) override {
    std::string line(text != nullptr ? text : "");
    line = line.substr(0, line.find('\n'));
    captured += line + "\n";
  }
  std::string captured;
};
vtkStandardNewMacro(CapturingOutputWindow)

} // namespace

struct VtkMessageCapture::Impl {
  vtkSmartPointer<vtkOutputWindow> previous;
  vtkSmartPointer<CapturingOutputWindow> window;
};

VtkMessageCapture::VtkMessageCapture() : impl_(new Impl) {
  impl_->previous = vtkOutputWindow::GetInstance();
  impl_->window = vtkSmartPointer<CapturingOutputWindow>::New();
  vtkOutputWindow::SetInstance(impl_->window);
}

VtkMessageCapture::~VtkMessageCapture() {
  vtkOutputWindow::SetInstance(impl_->previous);
  delete impl_;
}

std::string VtkMessageCapture::text() const { return impl_->window->captured; }

vtkSmartPointer<vtkPoints> toVtkPoints(const std::vector<Vec3>& positions) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(positions.size()));
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const auto& v = positions[i];
    points->SetPoint(static_cast<vtkIdType>(i), v.x(), v.y(), v.z());
  }
  return points;
}

void writeVtkXmlAtomically(vtkXMLWriter& writer, vtkDataObject* data, const std::filesystem::path& path) {
  const auto tmp = core::temporarySibling(path);
  writer.SetFileName(tmp.c_str());
  writer.SetInputData(data);
  writer.SetDataModeToAppended();
  writer.SetCompressorTypeToZLib();
  if (writer.Write() != 1) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    core::failInput(path.string(), "VTK could not write the file; check that the folder exists and is writable");
  }
  core::commitAtomicFile(tmp, path);
}

} // namespace armour::geometry
