#pragma once
// The heuristic workspace planner of thesis section 5.3.2: a radial approach to a fruit around its
// stem. In the (x, y) plane the path is given in polar coordinates about the stem (eq. 5.13-5.21):
// outside the plant circle of radius r_e it decays exponentially in radius while the polar angle
// turns (after s_a) to the fruit's angle, reached at the entry point s = s_e; from there it runs on
// a straight radial line to the fruit. Time scaling s(t) is a quintic with zero velocity and
// acceleration at both ends; height and Cardan angles reach their goals at the entry time t_e
// (eq. 5.23, 5.24). The trajectory is C2-smooth with zero velocity at both ends.
//
// Coordinates: everything in the task frame W. The polar angles are measured in the stem frame
// B_st whose x axis points from the reference point (the robot base, usually the W origin) through
// the stem (eq. 5.15), so the angle range [0, 2 pi) never wraps between robot and plant.
#include <Eigen/Core>
#include <array>
#include <string>

#include "common/defaults.hpp"

namespace armstudy {

struct ApproachPlannerOptions {
  double entry_radius_m = 0.1;  // r_e = d / 2, radius of the plant circle (Fig. 5.8: 0.1 m)
  double s_a = 0.1;             // path parameter where the polar angle starts to turn (Fig. 5.8)
  double s_e = 0.8;             // path parameter of the entry point (Fig. 5.8)
  double duration_s = 0;        // T, duration of the whole approach; must be positive
  double exp_scale_m = defaults::kApproachExpScale_m;  // L of r(s) = L e^{-a s} + b (thesis: 1 m)
  double alpha_goal_rad = 0;  // goal Cardan alpha, beta (fruit hanging straight down: 0, 0)
  double beta_goal_rad = 0;
  double gamma_offset_rad = 0;  // goal gamma = heading of the radial approach + this offset
  // False with a message for unusable values (duration <= 0, s_a >= s_e, ...).
  bool validate(std::string& error) const;
};

struct ApproachProblem {
  Eigen::Vector3d p_start_W = Eigen::Vector3d::Zero();       // r_s and z_s
  Eigen::Vector3d cardan_start = Eigen::Vector3d::Zero();    // (alpha, beta, gamma) at the start
  Eigen::Vector2d stem_xy_W = Eigen::Vector2d::Zero();       // r_st
  Eigen::Vector3d fruit_W = Eigen::Vector3d::Zero();         // r_g and z_g
  Eigen::Vector2d reference_xy_W = Eigen::Vector2d::Zero();  // robot base, origin of delta
};

// Planning outcomes that are results, not errors.
enum class ApproachStatus {
  Ok,
  StartInsidePlantCircle,   // |r_s - r_st| <= r_e: the radial approach cannot start outside
  FruitOutsidePlantCircle,  // |r_g - r_st| >= r_e: no entry point between start and fruit
  StartTooFar,              // r_s - r_e >= L: eq. (5.19a) has no real solution; raise exp_scale_m
};
const char* toString(ApproachStatus s);

// Polar path (eq. 5.13) and its derivatives with respect to the path parameter s.
struct PolarSample {
  double r = 0, dr = 0, ddr = 0;        // r, r', r''
  double phi = 0, dphi = 0, ddphi = 0;  // phi, phi', phi''
};

// Planar path point in W with derivatives with respect to s (eq. 5.21).
struct PathSample {
  PolarSample polar;
  Eigen::Vector2d xy, dxy, ddxy;
};

// Task-space sample w = (x, y, z, alpha, beta, gamma) (eq. 5.3) with time derivatives.
struct TaskSample {
  double t = 0, s = 0;
  Eigen::Matrix<double, 6, 1> w, wd, wdd;
};

class ApproachTrajectory {
 public:
  ApproachStatus status() const { return status_; }
  const ApproachPlannerOptions& options() const { return opt_; }
  double duration() const { return opt_.duration_s; }
  double entryTime() const { return t_e_; }            // t_e with s(t_e) = s_e
  double a() const { return a_; }                      // eq. (5.19a)
  double b() const { return b_; }                      // eq. (5.19b)
  const PolarSample& start() const { return start_; }  // phi_s = (r_s, phi_s)
  double phiGoal() const { return phi_g_; }
  double rGoal() const { return r_g_; }
  double delta() const { return delta_; }  // angle of the stem frame, eq. (5.15)
  Eigen::Vector2d entryPointXY() const;    // phi_e = (r_e, phi_g) in W
  Eigen::Vector3d goalCardan() const { return cardan_g_; }

  // Polar path r(s), phi(s) of eq. (5.17), (5.18), piecewise.
  PolarSample polar(double s) const;
  // The fifth-order polynomials r_bar(s), phi_bar(s) of eq. (5.17), (5.18) evaluated at any s (for
  // checking the boundary conditions of eq. 5.20 and plotting Fig. 5.5).
  PolarSample polynomialBranches(double s) const;
  PathSample path(double s) const;
  // Quintic time scaling s(t) and its derivatives.
  void timeScaling(double t, double& s, double& sd, double& sdd) const;
  TaskSample sample(double t) const;

 private:
  friend ApproachTrajectory planApproach(const ApproachProblem&, const ApproachPlannerOptions&);
  ApproachStatus status_ = ApproachStatus::Ok;
  ApproachPlannerOptions opt_;
  Eigen::Vector2d stem_;
  double delta_ = 0, a_ = 0, b_ = 0, r_g_ = 0, phi_g_ = 0, t_e_ = 0;
  PolarSample start_;
  std::array<double, 6> r_coef_{};          // r_bar in u = (s - s_e) / (1 - s_e)
  std::array<double, 6> phi_coef_{};        // phi_bar in u = (s - s_a) / (s_e - s_a)
  Eigen::Vector3d z_ab_start_, z_ab_goal_;  // (z, alpha, beta) at start and goal
  double gamma_s_ = 0;
  Eigen::Vector3d cardan_g_;
};

// The task-space sample as a pose reference for tracking: TCP position, velocity and acceleration,
// orientation R_WT = R(alpha, beta, gamma) * R_tool, angular velocity omega = T_A(alpha, beta) wd_o
// (eq. 5.7) and its derivative, all in W. R_tool maps the planner's tool frame (thesis convention:
// x along the approach, z up for alpha = beta = 0) to the design's TCP frame; e.g. Ry(pi/2) when
// the design's TCP z axis is the approach axis. A constant R_tool does not change omega.
struct PoseReference {
  Eigen::Vector3d p_WT, v_W, a_W;
  Eigen::Matrix3d R_WT;
  Eigen::Vector3d omega_W, omegad_W;
};
PoseReference poseReference(const TaskSample& w, const Eigen::Matrix3d& R_tool);

// Plans the approach. Options must validate (programmer precondition: readers turn bad files into
// InputError first). Geometric impossibilities are reported in status(); the trajectory is then
// not evaluable.
ApproachTrajectory planApproach(const ApproachProblem& problem,
                                const ApproachPlannerOptions& options);

// Quintic Hermite polynomial on u in [0, 1] from (p0, v0, a0) to (p1, v1, a1) (derivatives in u).
std::array<double, 6> quinticHermite(double p0, double v0, double a0, double p1, double v1,
                                     double a1);
// Value and first two derivatives (in u) of a polynomial with coefficients c[0] + c[1] u + ...
void evalPolynomial(const std::array<double, 6>& c, double u, double& p, double& dp, double& ddp);

}  // namespace armstudy
