#include <cmath>
#include <sstream>

#include "common/angles.hpp"
#include "common/format.hpp"
#include "stages/dexterity/dexterity_status.hpp"

// The study-wide parts of the dexterity stage's outputs: the settings in summary.json and the
// report's opening paragraphs.
namespace armstudy::dexterity {

namespace {

std::vector<std::string> obstacleNames(const std::vector<collision::Obstacle>& obstacles) {
  std::vector<std::string> n;
  for (const collision::Obstacle& o : obstacles) n.push_back(o.name);
  return n;
}

}  // namespace

// The study-wide fields of summary.json (grid and settings) with an empty design list.
nlohmann::ordered_json settingsJson(const DexterityOptions& options) {
  nlohmann::ordered_json js;
  const StemGrid& g = options.grid;
  js["grid"] = {
      {"stem_x_m", g.stem_x_m},
      {"stem_y_m", g.stem_y_m},
      {"radius_m", g.radius_m},
      {"gamma_rad",
       {{"min", g.gamma_rad.min}, {"max", g.gamma_rad.max}, {"count", g.gamma_rad.count}}},
      {"z_m", {{"min", g.z_m.min}, {"max", g.z_m.max}, {"count", g.z_m.count}}},
      {"task", toString(g.task)},
      {"roll_rad", g.roll_rad}};
  js["settings"] = {{"measure_space", metrics::toString(options.measure_space)},
                    {"w_joint_limits", options.w_joint_limits},
                    {"w_manipulability", options.w_manipulability},
                    {"w_transmission", options.w_transmission},
                    {"w_collision", options.w_collision},
                    {"collision_safety_distance_m", options.collision_safety_distance_m},
                    {"self_collision", options.collision.self},
                    {"clearance_m", options.collision.clearance_m},
                    {"obstacles", obstacleNames(options.collision.obstacles)},
                    {"joint_limit_activation", options.joint_limit_activation},
                    {"position_tolerance_m", options.position_tolerance_m},
                    {"orientation_tolerance_rad", options.orientation_tolerance_rad},
                    {"cold_starts", options.cold_starts},
                    {"nullspace_max_iterations", options.nullspace.max_iterations},
                    {"nullspace_relative_improvement", options.nullspace.relative_improvement},
                    {"nullspace_gradient_tolerance", options.nullspace.gradient_tolerance},
                    {"nullspace_quasi_newton", options.nullspace.quasi_newton},
                    {"search_seed_starts", options.seed_starts},
                    {"search_seed_stride", options.seed_stride},
                    {"search_propagation_rounds", options.propagation_rounds},
                    {"search_seed", options.search_seed},
                    {"chain_order", options.descending ? "descending" : "ascending"}};
  js["designs"] = nlohmann::ordered_json::array();
  return js;
}

// The report's title and opening paragraphs: the grid, the objective and how to read the images.
report::Document reportIntro(const DexterityOptions& options) {
  const StemGrid& g = options.grid;
  std::ostringstream grid;
  grid << "Stem at (" << formatFixedOr(g.stem_x_m, 3, "-") << ", "
       << formatFixedOr(g.stem_y_m, 3, "-") << ") m, TCP on a circle of radius "
       << formatFixedOr(g.radius_m, 3, "-") << " m, gamma "
       << formatFixedOr(g.gamma_rad.min * kRadToDeg, 1, "-") << ".."
       << formatFixedOr(g.gamma_rad.max * kRadToDeg, 1, "-") << " deg (" << g.gamma_rad.count
       << " values), z " << formatFixedOr(g.z_m.min, 2, "-") << ".."
       << formatFixedOr(g.z_m.max, 2, "-") << " m (" << g.z_m.count << " values), task "
       << toString(g.task) << ", measures on the " << metrics::toString(options.measure_space)
       << " Jacobian. Objective H = " << options.w_joint_limits << " H_j + "
       << options.w_manipulability << " H_m1 + " << options.w_transmission << " H_m2"
       << (options.w_collision > 0 ? " + " + formatG(options.w_collision, 3) + " H_c (d_a " +
                                         formatG(options.collision_safety_distance_m, 3) + " m)"
                                   : std::string())
       << " (thesis eq. 5.51). Collisions checked: "
       << (options.collision.enabled()
               ? std::string(options.collision.self ? "self-collision" : "") +
                     (options.collision.self && !options.collision.obstacles.empty() ? " and "
                                                                                     : "") +
                     (options.collision.obstacles.empty()
                          ? ""
                          : std::to_string(options.collision.obstacles.size()) + " obstacles")
               : std::string("none"))
       << "; a design without collision volumes is evaluated without them.";
  return report::Document()
      .heading(1, "Dexterity maps")
      .paragraph(grid.str())
      .paragraph("Images: x = gamma (left = " + formatFixedOr(g.gamma_rad.min * kRadToDeg, 0, "-") +
                 " deg), y = z (bottom = " + formatFixedOr(g.z_m.min, 2, "-") +
                 " m); colour viridis from 0 (dark) to 1 (yellow), colour bar right of each map "
                 "(bottom = 0, top = 1; the transmission map is scaled to its maximum); grey = not "
                 "reachable.");
}

}  // namespace armstudy::dexterity
