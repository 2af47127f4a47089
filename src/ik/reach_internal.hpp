#pragma once
// Private to ik/reach_solver.cpp and ik/local_solvers.cpp: a target prepared for the solver, its
// weighted residual and task Jacobian, and the local solvers (Levenberg-Marquardt with an active
// set on the joint limits; NLopt SLSQP with the limits as bounds; the W^-1-weighted damped Newton).
#include <Eigen/Core>

#include "ik/reach_solver.hpp"

namespace armstudy::ik_detail {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// What the solver needs about a target, prepared once per pose.
struct Context {
  const Model* model;  // null when only residuals/Jacobians are needed
  const PoseTask& target;
  double w_o;
  bool full_orientation;
  bool any_orientation;  // full pose or a selection of Cardan angles (not the tool-axis task)
  bool tool_axis;
  int m;  // residual rows (3 for the tool axis, whose rows have rank 2)
};

// Weighted residual e = W (w_d - f(q)) of the pose in kin (the m selected rows first, the rest
// zero), and the unweighted errors.
void residual(const Context& c, const KinematicsWorkspace& kin, Vec6& e, PoseError& err);
// Weighted task Jacobian rows matching residual() (unselected rows zero). False at the
// representation singularity.
bool taskJacobian(const Context& c, const KinematicsWorkspace& kin, Jacobian6& J);
bool withinTolerance(const PoseError& e, const IkOptions& o, double fraction);

// Outcome of one local solve.
struct LocalResult {
  bool success = false;
  bool singular = false;  // ended because the Cardan representation became singular
  PoseError err;
  double cost = 0;
};

// Levenberg-Marquardt on |W e|^2 projected onto the joint-limit box (active set). q is updated
// in place to the best configuration of this start; ws.kin holds its forward kinematics on return.
LocalResult runLm(const Context& c, IkWorkspace& ws, const IkOptions& o, JointVector& q,
                  bool limits, double lambda_initial, int& iterations);
// Minimises ikObjective from q (in place) with NLopt SLSQP; returns the local result.
LocalResult runSlsqp(const Context& c, IkWorkspace& ws, const IkOptions& o, JointVector& q);
// IkAlgorithm::WeightedNewton from q (in place; projected onto the limits first): damped Newton
// (Levenberg-Marquardt on eq. 3.2 with the geometric error of ik::taskJacobianAndError, angular
// rows scaled by kOrientationLength_m) weighted by W^-1 (o.joint_weights), iterates projected onto
// the joint limits, until both errors are below o's tolerances, o.max_iterations or a stall. q ends
// at the best iterate. Returns the iterations taken.
int runWeightedNewton(const Model& model, KinematicsWorkspace& ws, const PoseTask& target,
                      const IkOptions& o, JointVector& q);

}  // namespace armstudy::ik_detail
