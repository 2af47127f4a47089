#pragma once
// VTK XML writers for ParaView (docs/reachability.md lists the arrays the reachability stage
// writes). Generic so every stage can use them:
//  - ImageGrid -> .vti: a regular grid with origin and spacing in metres and named point arrays;
//  - PolyDataSet -> .vtp: points with named arrays, optional polylines and triangles;
//  - StructuredGridSet -> .vts: a curvilinear grid (e.g. a map on its cylinder around a stem);
//  - a .pvd collection: a time series of such files for ParaView.
// Every dataset carries field data (string lists, docs/paraview.md): "units", "legend", and
// "coordinates" (what the point coordinates are: world W in metres, or a parameter plane).
// Files are written atomically (temporary file, then rename). VTK types stay in vtk_io.cpp.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace armstudy::io {

enum class ArrayType { Float64, Float32, Int32, UInt8 };

// A named array of `components` values per point, stored as double and converted on writing.
struct NamedArray {
  std::string name;
  ArrayType type = ArrayType::Float64;
  int components = 1;
  std::vector<double> values;  // size = points * components, point-major
};

// Field data of a whole dataset: a named list of strings (vtkStringArray), e.g. "units" =
// {"manipulability: m^3", "position: m"}.
struct FieldStrings {
  std::string name;
  std::vector<std::string> values;
};
// The field data every armstudy VTK file carries (docs/paraview.md): "coordinates" (kWorldMetres
// or what else the point coordinates are), "units" ("<array>: <unit>" per array, "1" for
// dimensionless or counts) and, when some array holds an enumeration, "legend" ("<array> <value>:
// <meaning>").
inline constexpr const char* kWorldMetres = "world frame W [m]";
std::vector<FieldStrings> fieldData(std::vector<std::string> units,
                                    std::vector<std::string> legend = {},
                                    std::string coordinates = kWorldMetres);

struct ImageGrid {
  std::array<int, 3> dims{1, 1, 1};        // points per axis (x fastest)
  std::array<double, 3> origin{0, 0, 0};   // m
  std::array<double, 3> spacing{1, 1, 1};  // m
  std::vector<NamedArray> point_arrays;    // each with dims[0]*dims[1]*dims[2] tuples
  std::vector<FieldStrings> field_data;
  long points() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
};

struct PolyDataSet {
  std::vector<Eigen::Vector3d> points;        // m
  std::vector<NamedArray> point_arrays;       // each with points.size() tuples
  bool vertices = false;                      // one vertex cell per point (point clouds)
  std::vector<std::vector<int>> lines;        // polylines as point indices
  std::vector<std::array<int, 3>> triangles;  // surface triangles
  std::string active_tensors;                 // name of a 9-component array made the active
                                              // tensors (ParaView's Tensor Glyph), or empty
  std::vector<FieldStrings> field_data;
};

// A structured (curvilinear) grid: dims points per index axis (i fastest), each with its own
// position.
struct StructuredGridSet {
  std::array<int, 3> dims{1, 1, 1};
  std::vector<Eigen::Vector3d> points;   // m, dims[0]*dims[1]*dims[2], i fastest
  std::vector<NamedArray> point_arrays;  // each with points.size() tuples
  std::vector<FieldStrings> field_data;
};

// One step of a .pvd time series: its time and its file, relative to the .pvd's folder.
struct PvdStep {
  double time = 0;
  std::string file;
};

// Writes .vti / .vtp (XML, binary appended data, zlib-compressed). Checks array sizes.
void writeVti(const std::string& path, const ImageGrid& grid);
void writeVtp(const std::string& path, const PolyDataSet& poly);
void writeVts(const std::string& path, const StructuredGridSet& grid);
// Writes a ParaView collection file (.pvd, XML) listing the steps in order.
void writePvd(const std::string& path, const std::vector<PvdStep>& steps);

}  // namespace armstudy::io
