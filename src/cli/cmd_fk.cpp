#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/design_options.hpp"
#include "common/angles.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/units.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::cli {

// A warning for each joint value outside the joint's limits.
static std::vector<std::string> limitWarnings(const Model& m, const Eigen::VectorXd& q) {
  std::vector<std::string> warn;
  for (int i = 0; i < m.dof(); ++i) {
    const auto& L = m.joints[i].limits;
    if (q[i] < L.q_min || q[i] > L.q_max) warn.push_back(m.joints[i].name + " outside its limits");
  }
  return warn;
}

// Radian values beyond a full turn on revolute joints look like degrees: say so, with --deg.
static std::string degreesHint(const Model& m, const Eigen::VectorXd& q) {
  std::string names;
  for (int i = 0; i < m.dof(); ++i)
    if (m.joints[i].type == JointType::Revolute && std::abs(q[i]) > 2 * std::numbers::pi)
      names += (names.empty() ? "" : ", ") + m.joints[i].name;
  if (names.empty()) return "";
  return "values of " + names +
         " are beyond a full turn in radians: if they are degrees, add --deg";
}

void addFkCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string path;
    std::vector<double> q;
    bool deg = false, json = false;
    DesignSourceOptions src;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("design", a->path, "Design file (TOML, or URDF with --base/--tip)")->required();
  addDesignSourceOptions(cmd, a->src);
  cmd->add_option("--q", a->q,
                  "Joint values, comma-separated, one per joint: metres for prismatic joints,\n"
                  "radians for revolute joints (degrees with --deg)")
      ->delimiter(',')
      ->required();
  cmd->add_flag("--deg", a->deg, "Revolute joint values and printed angles are in degrees");
  cmd->add_flag("--json", a->json, "Machine-readable output");
  setAction(cmd, action, [a] {
    UrdfOptions uo = a->src.urdf();
    uo.collision = false;  // fk needs no collision volumes
    UrdfInfo info;
    const Model m = loadAnyDesign(a->path, uo, &info);
    const bool has_links = info.joints.size() == static_cast<std::size_t>(m.dof());
    if (static_cast<int>(a->q.size()) != m.dof())
      throw InputError("--q", 0, "q",
                       "got " + std::to_string(a->q.size()) + " joint values, design '" + m.name +
                           "' has " + std::to_string(m.dof()) + " joints");
    Eigen::VectorXd q(m.dof());
    for (int i = 0; i < m.dof(); ++i) {
      q[i] = a->q[i];
      if (a->deg && m.joints[i].type == JointType::Revolute) q[i] *= kDegToRad;
      const Dimension dim =
          m.joints[i].type == JointType::Revolute ? Dimension::Angle : Dimension::Length;
      if (const std::string bad = implausible(q[i], &dim); !bad.empty())
        throw InputError("--q", 0, "q", "joint " + m.joints[i].name + ": " + bad);
    }
    KinematicsWorkspace ws(m);
    forwardKinematics(m, ws, q);
    const double as = a->deg ? kRadToDeg : 1.0;
    const char* au = a->deg ? "deg" : "rad";
    struct Row {
      std::string name;
      Eigen::Vector3d p;
      CardanAngles c;
    };
    std::vector<Row> rows;
    // Joint rows: the body frame after each joint; for a URDF design its child link frame
    // (L_i = F_i R_FL), so every row agrees with URDF tools.
    for (int i = 0; i < m.dof(); ++i)
      rows.push_back({m.joints[i].name, ws.p_WF[i],
                      cardanForDisplay(has_links ? Eigen::Matrix3d(ws.R_WF[i] * info.joints[i].R_FL)
                                                 : Eigen::Matrix3d(ws.R_WF[i]))});
    rows.push_back({"tcp", ws.p_WT, cardanForDisplay(ws.R_WT)});
    std::vector<std::string> warn = limitWarnings(m, q);
    if (!a->deg)
      if (const std::string hint = degreesHint(m, q); !hint.empty()) warn.push_back(hint);
    if (a->json) {
      nlohmann::ordered_json j;
      j["design"] = m.name;
      j["angle_unit"] = au;
      j["q"] = a->q;
      j["frames"] = nlohmann::ordered_json::array();
      for (const auto& r : rows)
        j["frames"].push_back({{"frame", r.name},
                               {"x_m", r.p.x()},
                               {"y_m", r.p.y()},
                               {"z_m", r.p.z()},
                               {"alpha", r.c.alpha * as},
                               {"beta", r.c.beta * as},
                               {"gamma", r.c.gamma * as},
                               {"cardan_singular", r.c.singular}});
      j["warnings"] = warn;
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    std::printf("%-12s %10s %10s %10s %10s %10s %10s\n", "frame", "x [m]", "y [m]", "z [m]",
                (std::string("alpha[") + au + "]").c_str(),
                (std::string("beta[") + au + "]").c_str(),
                (std::string("gamma[") + au + "]").c_str());
    for (const auto& r : rows)
      std::printf("%-12s %10.5f %10.5f %10.5f %10.4f %10.4f %10.4f%s\n", r.name.c_str(), r.p.x(),
                  r.p.y(), r.p.z(), r.c.alpha * as, r.c.beta * as, r.c.gamma * as,
                  r.c.singular ? "  (Cardan singular: cos(beta)=0)" : "");
    for (const auto& w : warn) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return 0;
  });
}

}  // namespace armstudy::cli
