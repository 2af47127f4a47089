#include "io/vtk_io.hpp"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include "common/errors.hpp"
#include "io/files.hpp"

namespace armstudy::io {

namespace {

vtkSmartPointer<vtkDataArray> makeArray(const NamedArray& a, long tuples) {
  ARMSTUDY_CHECK(a.components >= 1, "array '" + a.name + "' needs at least one component");
  ARMSTUDY_CHECK(static_cast<long>(a.values.size()) == tuples * a.components,
                 "array '" + a.name + "' has the wrong number of values");
  vtkSmartPointer<vtkDataArray> arr;
  switch (a.type) {
    case ArrayType::Float64: arr = vtkSmartPointer<vtkDoubleArray>::New(); break;
    case ArrayType::Float32: arr = vtkSmartPointer<vtkFloatArray>::New(); break;
    case ArrayType::Int32: arr = vtkSmartPointer<vtkIntArray>::New(); break;
    case ArrayType::UInt8: arr = vtkSmartPointer<vtkUnsignedCharArray>::New(); break;
  }
  arr->SetName(a.name.c_str());
  arr->SetNumberOfComponents(a.components);
  arr->SetNumberOfTuples(tuples);
  for (long t = 0; t < tuples; ++t)
    for (int c = 0; c < a.components; ++c)
      arr->SetComponent(t, c, a.values[static_cast<std::size_t>(t * a.components + c)]);
  return arr;
}

template <class Writer>
void writeAtomic(Writer* w, const std::string& path) {
  w->SetDataModeToAppended();
  w->SetCompressorTypeToZLib();
  w->WriteToOutputStringOn();
  if (w->Write() != 1) throw InputError(path, 0, "", "VTK writer failed");
  writeFileAtomic(path, w->GetOutputString());
}

}  // namespace

void writeVti(const std::string& path, const ImageGrid& g) {
  vtkNew<vtkImageData> img;
  img->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  img->SetOrigin(g.origin[0], g.origin[1], g.origin[2]);
  img->SetSpacing(g.spacing[0], g.spacing[1], g.spacing[2]);
  for (const NamedArray& a : g.point_arrays) img->GetPointData()->AddArray(makeArray(a, g.points()));
  vtkNew<vtkXMLImageDataWriter> w;
  w->SetInputData(img);
  writeAtomic(w.GetPointer(), path);
}

void writeVtp(const std::string& path, const PolyDataSet& p) {
  vtkNew<vtkPolyData> poly;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(p.points.size()));
  for (std::size_t i = 0; i < p.points.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), p.points[i].x(), p.points[i].y(), p.points[i].z());
  poly->SetPoints(pts);
  const long n = static_cast<long>(p.points.size());
  auto checkIndex = [n](int i) { ARMSTUDY_CHECK(i >= 0 && i < n, "poly data cell index out of range"); };
  if (p.vertices) {
    vtkNew<vtkCellArray> verts;
    for (vtkIdType i = 0; i < n; ++i) verts->InsertNextCell(1, &i);
    poly->SetVerts(verts);
  }
  if (!p.lines.empty()) {
    vtkNew<vtkCellArray> lines;
    for (const auto& l : p.lines) {
      lines->InsertNextCell(static_cast<int>(l.size()));
      for (int i : l) {
        checkIndex(i);
        lines->InsertCellPoint(i);
      }
    }
    poly->SetLines(lines);
  }
  if (!p.triangles.empty()) {
    vtkNew<vtkCellArray> polys;
    for (const auto& t : p.triangles) {
      vtkIdType ids[3] = {t[0], t[1], t[2]};
      for (int i : t) checkIndex(i);
      polys->InsertNextCell(3, ids);
    }
    poly->SetPolys(polys);
  }
  for (const NamedArray& a : p.point_arrays) poly->GetPointData()->AddArray(makeArray(a, n));
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetInputData(poly);
  writeAtomic(w.GetPointer(), path);
}

}  // namespace armstudy::io
