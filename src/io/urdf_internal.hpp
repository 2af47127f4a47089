#pragma once
// Private to io/urdf_*.cpp: what the URDF importer shares with its collision-mesh part (element
// lines for messages, link frames, the collision volumes of a link from its <collision> elements).
#include <urdf_model/model.h>

#include <Eigen/Geometry>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "io/urdf_io.hpp"
#include "model/model.hpp"

namespace armstudy::defaults {
// Elements inside elements a URDF may nest (as toml++ nests TOML tables and arrays): the XML
// parsers recurse once per level. A URDF needs about six.
inline constexpr int kMaxXmlNesting = 256;
}  // namespace armstudy::defaults

namespace armstudy::urdf_detail {

// Lines of the URDF's elements (urdfdom keeps none), found with tinyxml, the parser urdfdom uses.
struct XmlIndex {
  int robot_line = 1;
  std::map<std::string, int> links, joints;     // element name -> line
  std::set<std::string> joints_without_bounds;  // <limit> without lower or upper
};

// The tag structure of an XML text (a URDF, a DAE mesh), read without building a tree: the line
// of the first tag that does not close the element open before it or has no element name, of a
// comment, CDATA section or tag left unterminated, or of an element left open (0 when the tags
// match).
struct XmlTagScan {
  int problem_line = 0;
};
// Scans the tags of `text`. Elements nested more than defaults::kMaxXmlNesting deep are an
// InputError(file, line, "xml") at the first too deep one: the XML parsers (TinyXML, assimp's)
// recurse once per level, and 60,000 nested elements overflow the stack.
XmlTagScan scanXmlTags(const std::string& text, const std::string& file);

// Checks the XML of a URDF (well-formed, one <robot>, named and unique links and joints, known
// joint types, defined parents and children, finite and plausible numbers, a tree) and indexes
// its element lines. Throws InputError at the element.
XmlIndex indexAndCheck(const std::string& text, const std::string& file);

Eigen::Isometry3d toIso(const urdf::Pose& p);

// One link's part of a body: the link and the transform from the body frame F to the link frame L.
struct LinkInBody {
  urdf::LinkConstSharedPtr link;
  Eigen::Isometry3d T_FL;
};

// Inertials of the links of one body, merged into one rigid body about its COM, in frame F (the
// parallel-axis theorem for each link's inertia at its own COM).
LinkInertia mergeInertials(const std::vector<LinkInBody>& links);

// A link off the chain that rides on a chain link: a fixed link beyond the tip, or a branch (a
// head, fingers) whose joints are held at a stated position.
struct OffChainLink {
  urdf::LinkConstSharedPtr link;
  std::string chain_link;  // the chain link it hangs from
  Eigen::Isometry3d T_CL =
      Eigen::Isometry3d::Identity();  // the chain link's frame -> this link's frame
  std::vector<std::string> held;      // the movable joints on the way, "'name' at q"
};
// Every link below the chain's links that is not on it (`on_chain`), with its transform from the
// chain link it hangs from. Branch joints are held at q = 0, clamped into their limits (a
// continuous joint at 0; floating and planar joints at their origin).
std::vector<OffChainLink> offChainLinks(const urdf::ModelInterface& robot,
                                        const std::set<std::string>& on_chain);

// The collision volumes of one link of body `body`: primitives as swept-sphere volumes, meshes
// (resolved through package:// folders, read with assimp) fitted with swept-sphere volumes (CGAL).
// Mesh content hashes are appended to mesh_hashes, notes to warnings.
void addCollision(Model& m, int body, const LinkInBody& lb, const std::string& file,
                  const UrdfOptions& o, const XmlIndex& xml, std::vector<std::string>& warnings,
                  std::string& mesh_hashes);

// Why a movable joint is no arm joint ("" when it is one, or when it is fixed): floating and
// planar joints, mimic joints, and with `by_name` gripper or finger joints (named so: finger,
// gripper, jaw, thumb, knuckle, hand in the joint's name, the same but hand in its child link's).
std::string notArmJointReason(const urdf::Joint& j, bool by_name = true);

// The chains of arm joints below `base` and the default tip: the end of the longest chain, carried
// on along the fixed joints after it while they form one path (a flange, then tool0).
// When no chain has an arm joint but gripper or finger joints lead somewhere (a hand or a finger
// on its own), their chain is taken, names aside, and the reason says so.
UrdfChains findChains(const urdf::ModelInterface& robot, const urdf::LinkConstSharedPtr& base);
// The same with the gripper names judged (`by_name`) or not.
UrdfChains findChains(const urdf::ModelInterface& robot, const urdf::LinkConstSharedPtr& base,
                      bool by_name);

// The last link of the fixed joints after `link` when they form one path (fixed joints to finger
// parts and sensor frames aside, and with `axis`, the last arm joint's axis in link's frame, a
// branch's frames more than 1 mm off it when one branch is on it; their child links go to
// `fingers` when the path leads past `link`), else `link`.
std::string fixedPathEnd(const urdf::ModelInterface& robot, const std::string& link,
                         std::vector<std::string>* fingers = nullptr,
                         const urdf::Vector3* axis = nullptr);

}  // namespace armstudy::urdf_detail
