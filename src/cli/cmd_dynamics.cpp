#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/design_options.hpp"
#include "common/angles.hpp"
#include "common/errors.hpp"
#include "dynamics/dynamics.hpp"
#include "io/design_io.hpp"
#include "io/units.hpp"

namespace armstudy::cli {

void addDynamicsCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string path;
    std::vector<double> q, qd, qdd, gravity;
    bool deg = false, json = false, no_payload = false, rotor = false, mass_matrix = false;
    DesignSourceOptions src;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("design", a->path, "Design file (TOML, or URDF with --base/--tip)")->required();
  addDesignSourceOptions(cmd, a->src);
  cmd->add_option("--q", a->q, "Joint positions, one per joint (m / rad, deg with --deg)")
      ->delimiter(',')
      ->required();
  cmd->add_option("--qd", a->qd, "Joint velocities (m/s / rad/s, deg/s with --deg); default 0")
      ->delimiter(',');
  cmd->add_option("--qdd", a->qdd,
                  "Joint accelerations (m/s^2 / rad/s^2, deg/s^2 with --deg); default 0")
      ->delimiter(',');
  cmd->add_option("--gravity", a->gravity, "Gravity vector in W [m/s^2], default 0,0,-9.81")
      ->delimiter(',')
      ->expected(3);
  cmd->add_flag("--deg", a->deg, "Revolute joint values in degrees");
  cmd->add_flag("--no-payload", a->no_payload, "Ignore the [payload] at the TCP");
  cmd->add_flag("--rotor-inertia", a->rotor,
                "Add the reflected rotor inertias N^2 J_rotor of [[drive]]");
  cmd->add_flag("--mass-matrix", a->mass_matrix, "Also print M(q)");
  cmd->add_flag("--json", a->json, "Machine-readable output");
  setAction(cmd, action, [a] {
    UrdfOptions uo = a->src.urdf();
    uo.collision = false;
    UrdfInfo info;
    const Model m = loadAnyDesign(a->path, uo, &info);
    const int n = m.dof();
    // URDF <limit effort> (also `max_effort` in a design TOML): |Q| above it is reported.
    auto effort = [&](int i) {
      return info.joints.size() == static_cast<std::size_t>(n) ? info.joints[i].effort_max : 0.0;
    };
    auto vec = [&](const std::vector<double>& v, const char* key) {
      Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
      if (v.empty() && std::string(key) != "q") return out;
      if (static_cast<int>(v.size()) != n)
        throw InputError(std::string("--") + key, 0, key,
                         "got " + std::to_string(v.size()) + " values, design '" + m.name +
                             "' has " + std::to_string(n) + " joints");
      for (int i = 0; i < n; ++i) {
        out[i] = v[i];
        if (a->deg && m.joints[i].type == JointType::Revolute) out[i] *= kDegToRad;
        const bool rev = m.joints[i].type == JointType::Revolute, pos = std::string(key) == "q",
                   vel = std::string(key) == "qd";
        const Dimension dim = pos ? (rev ? Dimension::Angle : Dimension::Length)
                                  : (rev ? Dimension::AngularVelocity : Dimension::LinearVelocity);
        if (const std::string bad = implausible(out[i], pos || vel ? &dim : nullptr); !bad.empty())
          throw InputError(std::string("--") + key, 0, key,
                           "joint " + m.joints[i].name + ": " + bad);
      }
      return out;
    };
    const Eigen::VectorXd q = vec(a->q, "q"), qd = vec(a->qd, "qd"), qdd = vec(a->qdd, "qdd");
    DynamicsOptions opt;
    opt.include_payload = !a->no_payload;
    opt.include_rotor_inertia = a->rotor;
    if (!a->gravity.empty()) opt.g_W = Eigen::Vector3d(a->gravity[0], a->gravity[1], a->gravity[2]);
    std::string err;
    if (!opt.validate(err)) throw InputError("--gravity", 0, "gravity", err);
    const RigidBodyModel rbm = makeRigidBodyModel(m, opt);
    DynamicsWorkspace ws(rbm);
    Eigen::VectorXd Q(n), g(n);
    inverseDynamics(rbm, ws, q, qd, qdd, Q);
    gravityForces(rbm, ws, q, g);
    massMatrix(rbm, ws, q);
    if (a->json) {
      nlohmann::ordered_json j;
      j["design"] = m.name;
      j["gravity_W"] = {opt.g_W.x(), opt.g_W.y(), opt.g_W.z()};
      j["payload"] = opt.include_payload;
      j["rotor_inertia"] = opt.include_rotor_inertia;
      j["joints"] = nlohmann::ordered_json::array();
      for (int i = 0; i < n; ++i) {
        nlohmann::ordered_json row = {
            {"joint", m.joints[i].name},
            {"unit", m.joints[i].type == JointType::Revolute ? "N m" : "N"},
            {"Q", Q[i]},
            {"gravity", g[i]}};
        if (effort(i) > 0) {
          row["effort_limit"] = effort(i);
          row["over_effort_limit"] = std::abs(Q[i]) > effort(i);
        }
        j["joints"].push_back(row);
      }
      if (a->mass_matrix) {
        j["mass_matrix"] = nlohmann::ordered_json::array();
        for (int r = 0; r < n; ++r) {
          std::vector<double> row(n);
          for (int c = 0; c < n; ++c) row[c] = ws.M(r, c);
          j["mass_matrix"].push_back(row);
        }
      }
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    std::printf("%-8s %-4s %14s %14s\n", "joint", "unit", "Q", "g(q)");
    for (int i = 0; i < n; ++i)
      std::printf("%-8s %-4s %14.6f %14.6f%s\n", m.joints[i].name.c_str(),
                  m.joints[i].type == JointType::Revolute ? "N m" : "N", Q[i], g[i],
                  effort(i) > 0 && std::abs(Q[i]) > effort(i)
                      ? ("  over the effort limit " + std::to_string(effort(i))).c_str()
                      : "");
    if (a->mass_matrix) {
      std::printf("M(q):\n");
      for (int r = 0; r < n; ++r) {
        for (int c = 0; c < n; ++c) std::printf(" %12.6f", ws.M(r, c));
        std::printf("\n");
      }
    }
    return 0;
  });
}

}  // namespace armstudy::cli
