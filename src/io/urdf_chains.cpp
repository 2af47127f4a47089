// The chains of arm joints below a URDF base link, and the default tip chosen among them
// (docs/design-format.md, "URDF designs": the default chain).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "common/join.hpp"
#include "io/urdf_internal.hpp"

namespace armstudy::urdf_detail {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Words that mark a gripper or hand joint in a joint's name, or (`hand` aside: the joint that
// moves a hand body is a wrist joint, as in iCub's r_wrist_yaw -> r_hand) in its child link's.
bool namesAGripper(const std::string& name, bool hand_counts = true) {
  const std::string n = lower(name);
  for (const char* w : {"finger", "gripper", "jaw", "thumb", "knuckle", "hand"})
    if ((hand_counts || std::string(w) != "hand") && n.find(w) != std::string::npos) return true;
  return false;
}

// Words that mark a finger part (not the hand or gripper body, which may carry the tool frame) in
// a fixed joint's or its child link's name.
bool namesAFinger(const std::string& name) {
  const std::string n = lower(name);
  for (const char* w : {"finger", "thumb", "jaw", "knuckle"})
    if (n.find(w) != std::string::npos) return true;
  return false;
}

// Words (between '_', '-' or '.') that mark a sensor frame (an LED, an IMU, a camera, a laser)
// in a fixed joint's or its child link's name.
bool namesASensor(const std::string& name) {
  const std::string n = lower(name);
  std::size_t b = 0;
  while (b <= n.size()) {
    std::size_t e = n.find_first_of("_-.", b);
    if (e == std::string::npos) e = n.size();
    const std::string w = n.substr(b, e - b);
    for (const char* s :
         {"led", "imu", "accelerometer", "camera", "optical", "laser", "lidar", "sensor"})
      if (w == s) return true;
    b = e + 1;
  }
  return false;
}

}  // namespace

std::string notArmJointReason(const urdf::Joint& j, bool by_name) {
  switch (j.type) {
    case urdf::Joint::FLOATING:
      return "floating joint";
    case urdf::Joint::PLANAR:
      return "planar joint";
    case urdf::Joint::FIXED:
      return "";
    default:
      break;
  }
  if (j.mimic) return "mimic joint";
  if (by_name && (namesAGripper(j.name) || namesAGripper(j.child_link_name, false)))
    return "gripper or finger joint";
  return "";
}

// Walks the tree below `base` (an explicit stack: a file may hold very long chains): fixed joints
// keep the count, arm joints add one, any other movable joint ends the chain there (it and its
// subtree are left out). An arm joint's child link is an end unless another arm joint follows.
UrdfChains findChains(const urdf::ModelInterface& robot, const urdf::LinkConstSharedPtr& base) {
  UrdfChains out = findChains(robot, base, true);
  if (!out.ends.empty()) return out;
  // Only gripper or finger joints below the base (a hand or a finger on its own): their chain is
  // the arm, names aside.
  UrdfChains named = findChains(robot, base, false);
  if (named.ends.empty()) return out;
  named.reason = "no arm joint below '" + base->name +
                 "' except joints named as gripper or finger joints, so these are the chain; " +
                 named.reason + " (another tip: --tip, tip_link in a study)";
  return named;
}

UrdfChains findChains(const urdf::ModelInterface& robot, const urdf::LinkConstSharedPtr& base,
                      bool by_name) {
  UrdfChains out;
  out.base = base->name;
  struct Item {
    urdf::LinkConstSharedPtr link;
    int joints;  // arm joints from the base to `link`
    int end;     // the chain end `link` belongs to (index into ends; -1: the base, root)
  };
  UrdfChainEnd root{base->name, 0, {}, {}};
  std::vector<UrdfChainEnd> ends;
  std::vector<bool> followed;  // an arm joint follows ends[i]: no end
  std::vector<Item> stack{{base, 0, -1}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    for (const auto& j : it.link->child_joints) {
      const auto child = robot.getLink(j->child_link_name);
      UrdfChainEnd& at = it.end < 0 ? root : ends[it.end];
      if (j->type == urdf::Joint::FIXED) {
        at.fixed_frames.push_back(child->name);
        stack.push_back({child, it.joints, it.end});
      } else if (const std::string why = notArmJointReason(*j, by_name); !why.empty()) {
        at.left_out.push_back(j->name + " (" + why + ")");
      } else {
        if (it.end >= 0) followed[it.end] = true;
        ends.push_back({child->name, it.joints + 1, {}, {}});
        followed.push_back(false);
        stack.push_back({child, it.joints + 1, static_cast<int>(ends.size()) - 1});
      }
    }
  }
  for (std::size_t i = 0; i < ends.size(); ++i)
    if (!followed[i]) out.ends.push_back(ends[i]);
  std::stable_sort(
      out.ends.begin(), out.ends.end(),
      [](const UrdfChainEnd& a, const UrdfChainEnd& b) { return a.joints > b.joints; });
  if (out.ends.empty()) {
    out.reason = "no arm joint below '" + base->name + "'";
    if (!root.left_out.empty()) out.reason += " (left out: " + join(root.left_out, ", ") + ")";
    return out;
  }
  std::vector<std::string> longest;
  for (const auto& e : out.ends)
    if (e.joints == out.ends.front().joints) longest.push_back(e.link);
  if (longest.size() > 1) {
    std::sort(longest.begin(), longest.end());
    out.reason = "the longest chains of arm joints (" + std::to_string(out.ends.front().joints) +
                 ") end in several links: " + join(longest, ", ");
    return out;
  }
  const UrdfChainEnd& e = out.ends.front();
  std::vector<std::string> fingers;
  const auto end_joint = robot.getLink(e.link)->parent_joint;
  out.chosen = fixedPathEnd(robot, e.link, &fingers, &end_joint->axis);
  out.reason =
      "the longest chain of arm joints (" + std::to_string(e.joints) + ") ends in '" + e.link + "'";
  if (out.chosen != e.link)
    out.reason +=
        "; the fixed frames after it form one path" +
        (fingers.empty()
             ? ""
             : " (finger, sensor and off-axis frames aside: " + join(fingers, ", ") + ")") +
        ", ending in '" + out.chosen + "'";
  if (!e.left_out.empty()) out.reason += "; left out: " + join(e.left_out, ", ");
  return out;
}

namespace {

// Distance of `p` from the line through the origin along `axis` (unit or not; 0-length: |p|).
double offAxis(const urdf::Vector3& p, const urdf::Vector3& axis) {
  const double a2 = axis.x * axis.x + axis.y * axis.y + axis.z * axis.z;
  const double along = a2 > 0 ? (p.x * axis.x + p.y * axis.y + p.z * axis.z) / a2 : 0.0;
  const double dx = p.x - along * axis.x, dy = p.y - along * axis.y, dz = p.z - along * axis.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

// The last link of the fixed joints after `link` when they form one path, else `link`. Fixed
// joints to finger parts (fixed fingers, as some hands are written) and to sensor frames (an LED,
// an accelerometer on the palm) are not part of the path; their child links go to `fingers`. With
// `axis` (the last arm joint's axis in `link`'s frame, through its origin), where the path
// branches and exactly one branch stays on that axis (within kTipOnAxis_m), it is followed and the
// frames off the axis (side markers) go to `fingers` too.
std::string fixedPathEnd(const urdf::ModelInterface& robot, const std::string& link,
                         std::vector<std::string>* fingers, const urdf::Vector3* axis) {
  constexpr double kTipOnAxis_m = 1e-3;
  std::string cur = link;
  urdf::Pose at;  // cur's frame in link's
  std::vector<std::string> skipped;
  for (;;) {
    const auto l = robot.getLink(cur);
    std::vector<std::pair<std::string, urdf::Pose>> fixed;
    for (const auto& j : l->child_joints) {
      if (j->type != urdf::Joint::FIXED) continue;
      urdf::Pose next;
      next.position = at.position + at.rotation * j->parent_to_joint_origin_transform.position;
      next.rotation = at.rotation * j->parent_to_joint_origin_transform.rotation;
      if (namesAFinger(j->name) || namesAFinger(j->child_link_name) || namesASensor(j->name) ||
          namesASensor(j->child_link_name))
        skipped.push_back(j->child_link_name);
      else
        fixed.push_back({j->child_link_name, next});
    }
    if (fixed.size() > 1 && axis) {  // a branch: the frames on the axis, side markers aside
      std::vector<std::pair<std::string, urdf::Pose>> on;
      std::vector<std::string> off;
      for (const auto& f : fixed)
        if (offAxis(f.second.position, *axis) > kTipOnAxis_m)
          off.push_back(f.first);
        else
          on.push_back(f);
      if (on.size() == 1) {
        fixed = on;
        skipped.insert(skipped.end(), off.begin(), off.end());
      }
    }
    if (fixed.size() > 1) return link;
    if (fixed.empty()) {
      if (fingers && cur != link) *fingers = skipped;
      return cur;
    }
    cur = fixed.front().first;
    at = fixed.front().second;
  }
}

}  // namespace armstudy::urdf_detail
