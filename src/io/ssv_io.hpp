#pragma once
// Reading swept-sphere-volume geometry from TOML tables: the design's [[collision]] volumes (link
// frame) and a study's [[obstacle]] entries (task frame W) share one format (docs/collision.md):
//   type = "point" | "line" | "triangle"   (obstacles also accept "sphere" and "capsule")
//   points = [[x, y, z], ...]               (1, 2 or 3 points; numbers in metres or "230 mm")
//   radius = "40 mm"
#include <Eigen/Core>
#include <array>
#include <string>

#include "model/model.hpp"

namespace armstudy::io {

class TableReader;

struct SsvGeometry {
  SsvType type = SsvType::Point;
  std::array<Eigen::Vector3d, 3> p{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                   Eigen::Vector3d::Zero()};
  double radius_m = 0;
};

// Reads type, points and radius from `r` and checks the geometry (collision::volumeGeometryProblem:
// negative radius, coincident or collinear points). `frame` names the frame the points are given
// in, for messages ("the link frame", "the task frame W"). Throws InputError (file, line, key).
SsvGeometry readSsvGeometry(TableReader& r, bool allow_obstacle_names, const std::string& frame);

}  // namespace armstudy::io
