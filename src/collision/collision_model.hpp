#pragma once
// Checks and helpers on the collision part of a Model (model/model.hpp: CollisionVolume,
// CollisionModel). Parsing lives in io/design_io; geometry in collision/distance.
#include <string>

#include "model/model.hpp"

namespace armstudy::collision {

// Why a volume's geometry is unusable, or "" when it is fine: a negative or non-finite radius,
// non-finite coordinates, coincident points of a line, coincident or collinear corners of a
// triangle (closer than defaults::kCollisionCoincident_m to the line through the other two).
std::string volumeGeometryProblem(SsvType type, const std::array<Eigen::Vector3d, 3>& p,
                                  double radius_m);

// Name of a body for messages and files: "base" for -1, else the joint name.
std::string bodyName(const Model& model, int link);
// Inverse of bodyName; -2 when there is no such body.
int bodyIndex(const Model& model, const std::string& name);

// True when links a and b (joint index, -1 = base) are checked against each other: different,
// not neighbours in the chain (|a - b| = 1), and not in the design's allowed pairs.
bool isCollisionPair(const Model& model, int a, int b);

}  // namespace armstudy::collision
