#pragma once
// VTK XML writers for ParaView (docs/reachability.md lists the arrays the reachability stage
// writes). Generic so every stage can use them:
//  - ImageGrid -> .vti: a regular grid with origin and spacing in metres and named point arrays;
//  - PolyDataSet -> .vtp: points with named arrays, optional polylines and triangles.
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

struct ImageGrid {
  std::array<int, 3> dims{1, 1, 1};          // points per axis (x fastest)
  std::array<double, 3> origin{0, 0, 0};     // m
  std::array<double, 3> spacing{1, 1, 1};    // m
  std::vector<NamedArray> point_arrays;      // each with dims[0]*dims[1]*dims[2] tuples
  long points() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
};

struct PolyDataSet {
  std::vector<Eigen::Vector3d> points;            // m
  std::vector<NamedArray> point_arrays;           // each with points.size() tuples
  bool vertices = false;                          // one vertex cell per point (point clouds)
  std::vector<std::vector<int>> lines;            // polylines as point indices
  std::vector<std::array<int, 3>> triangles;      // surface triangles
};

// Writes .vti / .vtp (XML, binary appended data, zlib-compressed). Checks array sizes.
void writeVti(const std::string& path, const ImageGrid& grid);
void writeVtp(const std::string& path, const PolyDataSet& poly);

}  // namespace armstudy::io
