#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/design_options.hpp"
#include "common/angles.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/join.hpp"
#include "engine/run.hpp"
#include "io/design_io.hpp"
#include "io/urdf_arm.hpp"
#include "model/model_notes.hpp"

namespace armstudy::cli {

static std::string fmtQ(const Joint& j, double v) {
  if (j.type == JointType::Revolute) return padLeft(formatFixed(toDegrees(v), 1), 8) + " deg";
  return padLeft(formatFixed(v, 3), 8) + " m  ";
}

// The links `--tip` can name besides `tip`: each chain's end and the fixed frames after it.
static std::vector<std::string> otherTips(const UrdfChains& c, const std::string& tip) {
  std::vector<std::string> others;
  for (const auto& e : c.ends) {
    if (e.link != tip) others.push_back(e.link);
    for (const auto& f : e.fixed_frames)
      if (f != tip) others.push_back(f);
  }
  return others;
}

// The chains of a URDF design, the tip chosen and why, and the --tip for the others.
static void printChains(const UrdfChains& c, const std::string& tip_given) {
  std::printf(
      "\nchains below '%s' (a chain runs over arm joints; gripper, finger, mimic, "
      "floating and planar joints end it):\n",
      c.base.c_str());
  for (const auto& e : c.ends) {
    std::printf("  %-24s %2d joints", e.link.c_str(), e.joints);
    if (!e.fixed_frames.empty())
      std::printf("   fixed frames after it: %s", join(e.fixed_frames, ", ").c_str());
    if (!e.left_out.empty()) std::printf("   left out: %s", join(e.left_out, ", ").c_str());
    std::printf("\n");
  }
  if (!tip_given.empty())
    std::printf("tip      '%s' (--tip)\n", tip_given.c_str());
  else if (!c.chosen.empty())
    std::printf("tip      '%s' (default: %s)\n", c.chosen.c_str(), c.reason.c_str());
  else
    std::printf("tip      none by default: %s\n", c.reason.c_str());
  std::vector<std::string> others = otherTips(c, tip_given.empty() ? c.chosen : tip_given);
  for (auto& o : others) o = "--tip " + o;
  if (!others.empty()) std::printf("other tips: %s\n", join(others, ", ").c_str());
}

// The same as JSON (describe --json, key "urdf_chains"; docs/design-format.md).
static nlohmann::ordered_json chainsJson(const UrdfChains& c, const std::string& tip_given) {
  nlohmann::ordered_json j;
  j["base"] = c.base;
  j["chains"] = nlohmann::ordered_json::array();
  for (const auto& e : c.ends)
    j["chains"].push_back({{"end", e.link},
                           {"joints", e.joints},
                           {"fixed_frames", e.fixed_frames},
                           {"left_out", e.left_out}});
  const std::string& tip = tip_given.empty() ? c.chosen : tip_given;
  j["tip"] = tip.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(tip);
  j["tip_from"] = !tip_given.empty() ? "--tip" : tip.empty() ? "none" : "default";
  j["default_tip"] = c.chosen.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(c.chosen);
  j["default_reason"] = c.reason;
  j["other_tips"] = otherTips(c, tip);
  return j;
}

void addDescribeCommand(CLI::App* cmd, Action& action) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto src = std::make_shared<DesignSourceOptions>();
  cmd->add_option("design", *path,
                  "Design file (TOML or URDF), e.g. designs/final_prototype_9dof.toml")
      ->required();
  addDesignSourceOptions(cmd, *src);
  cmd->add_flag("--json", *json, "Print the resolved table as JSON (SI units)");
  setAction(cmd, action, [path, json, src] {
    std::optional<UrdfChains> chains;
    if (isUrdfPath(*path)) chains = findUrdfChains(*path, src->urdf());
    Model m;
    try {
      m = loadAnyDesign(*path, src->urdf());
    } catch (const InputError&) {
      // the way out of an ambiguous or bad chain
      if (chains && *json)
        std::cout << nlohmann::ordered_json{{"urdf_chains", chainsJson(*chains, src->tip)}}.dump(2)
                  << "\n";
      else if (chains)
        printChains(*chains, src->tip);
      throw;
    }
    if (*json) {
      if (!chains) {
        std::cout << modelToJson(m) << "\n";
        return 0;
      }
      auto j = nlohmann::ordered_json::parse(modelToJson(m));
      j["urdf_chains"] = chainsJson(*chains, src->tip);
      const ArmToolAxis a = lastJointAxisInTcp(m);
      j["last_joint_axis_tcp"] = {a.axis_T.x(), a.axis_T.y(), a.axis_T.z()};
      j["tcp_off_last_axis_m"] = a.off_axis_m;
      j["tool_axis_from"] = notes::toolAxisFrom(m);
      j["tool_axis_open"] = notes::toolAxisOpen(m);
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    std::printf("design   %s  (%d DoF)\n", m.name.c_str(), m.dof());
    if (!m.description.empty()) std::printf("about    %s\n", m.description.c_str());
    if (!m.source.empty()) std::printf("source   %s\n", m.source.c_str());
    std::printf("file     %s  [%s]\n\n", m.file.c_str(), m.file_hash.c_str());
    int w = 12;  // joint name column: wider for long (URDF) names
    for (const Joint& j : m.joints) w = std::max(w, static_cast<int>(j.name.size()));
    std::printf("%-3s %-*s %-9s %8s %8s %8s %9s %9s %9s   %-12s %-12s\n", "#", w, "joint", "type",
                "x [m]", "y [m]", "z [m]", "alpha[deg]", "beta[deg]", "gamma[deg]", "min", "max");
    int i = 1;
    for (const Joint& j : m.joints) {
      const double d = kRadToDeg;
      std::printf("%-3d %-*s %-9s %8.4f %8.4f %8.4f %9.2f %9.2f %9.2f   %s %s\n", i++, w,
                  j.name.c_str(), toString(j.type), j.offset.x, j.offset.y, j.offset.z,
                  j.offset.alpha * d, j.offset.beta * d, j.offset.gamma * d,
                  fmtQ(j, j.limits.q_min).c_str(), fmtQ(j, j.limits.q_max).c_str());
    }
    const double d = kRadToDeg;
    std::printf("tcp %-*s %8.4f %8.4f %8.4f %9.2f %9.2f %9.2f\n", w + 10, "(from last frame)",
                m.tcp.x, m.tcp.y, m.tcp.z, m.tcp.alpha * d, m.tcp.beta * d, m.tcp.gamma * d);
    if (chains) {
      const ArmToolAxis a = lastJointAxisInTcp(m);
      std::printf(
          "last joint axis (TCP frame): %.4f %.4f %.4f  (joint '%s'; nearest TCP axis %s, %.3g "
          "deg; TCP %.1f mm off the axis, %.1f mm along it)\n",
          a.axis_T.x() + 0.0, a.axis_T.y() + 0.0, a.axis_T.z() + 0.0, a.joint.c_str(),
          a.nearest.c_str(), toDegrees(a.nearest_angle_rad), a.off_axis_m * 1e3,
          a.along_m * 1e3 + 0.0);
    }
    std::printf(
        "tool axis (TCP frame): %.4f %.4f %.4f  (what the spraying and stem tasks point at their "
        "targets; from %s)\n",
        m.tool_axis_T.x() + 0.0, m.tool_axis_T.y() + 0.0, m.tool_axis_T.z() + 0.0,
        notes::toolAxisFrom(m).c_str());
    if (!notes::toolAxisOpen(m).empty())
      std::printf("tool axis open: %s\n", notes::toolAxisOpen(m).c_str());
    if (!m.drives.empty()) std::printf("\ndrives: %zu\n", m.drives.size());
    if (!m.inertias.empty()) {
      std::printf("link inertias: given; mass per body (the link after each joint):");
      for (std::size_t i = 0; i < m.inertias.size() && i < m.joints.size(); ++i)
        std::printf("%s %s %.4g kg", i ? "," : "", m.joints[i].name.c_str(),
                    m.inertias[i].given ? m.inertias[i].mass_kg : 0.0);
      std::printf("\n");
    }
    if (!notes::all(m, notes::kLumped).empty()) {
      std::printf("lumped onto chain links (masses off the chain, for dynamics):\n");
      for (const auto& l : notes::all(m, notes::kLumped)) std::printf("  - %s\n", l.c_str());
    }
    if (!notes::all(m, notes::kNoCollision).empty()) {
      std::printf("links without collision volumes (self-collision does not cover them):\n");
      for (const auto& l : notes::all(m, notes::kNoCollision)) std::printf("  - %s\n", l.c_str());
    }
    if (!m.collision.empty()) std::printf("collision volumes: %zu\n", m.collision.volumes.size());
    if (!m.assumptions.empty()) {
      std::printf("\nassumptions (values the thesis does not give):\n");
      for (const auto& a : m.assumptions) std::printf("  - %s\n", a.c_str());
    }
    if (chains) printChains(*chains, src->tip);
    return 0;
  });
}

}  // namespace armstudy::cli
