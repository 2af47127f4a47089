#pragma once
// Private to io/urdf_*.cpp: what the URDF importer shares with its collision-mesh part (element
// lines for messages, link frames, the collision volumes of a link from its <collision> elements).
#include <urdf_model/model.h>

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "io/urdf_io.hpp"
#include "model/model.hpp"

namespace armstudy::urdf_detail {

// Lines of the URDF's elements (urdfdom keeps none), found with tinyxml, the parser urdfdom uses.
struct XmlIndex {
  int robot_line = 1;
  std::map<std::string, int> links, joints;  // element name -> line
};

Eigen::Isometry3d toIso(const urdf::Pose& p);

// One link's part of a body: the link and the transform from the body frame F to the link frame L.
struct LinkInBody {
  urdf::LinkConstSharedPtr link;
  Eigen::Isometry3d T_FL;
};

// The collision volumes of one link of body `body`: primitives as swept-sphere volumes, meshes
// (resolved through package:// folders, read with assimp) fitted with swept-sphere volumes (CGAL).
// Mesh content hashes are appended to mesh_hashes, notes to warnings.
void addCollision(Model& m, int body, const LinkInBody& lb, const std::string& file,
                  const UrdfOptions& o, const XmlIndex& xml, std::vector<std::string>& warnings,
                  std::string& mesh_hashes);

}  // namespace armstudy::urdf_detail
