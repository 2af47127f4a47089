#include "trajectory/approach_planner.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/enum_names.hpp"
#include "common/errors.hpp"

namespace armstudy {
namespace {

// Footnote of eq. (5.14): atan2 in (-pi, pi] mapped to [0, 2 pi) by adding 2 pi to negative values.
double polarAngle(double xi, double eta) {
  const double phi = std::atan2(eta, xi);
  return phi < 0 ? phi + 2.0 * std::numbers::pi : phi;
}

double wrapToPi(double x) {
  x = std::fmod(x + std::numbers::pi, 2.0 * std::numbers::pi);
  if (x < 0) x += 2.0 * std::numbers::pi;
  return x - std::numbers::pi;
}

// Rest-to-rest quintic sigma(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 and its derivatives in tau.
void restToRest(double tau, double& p, double& dp, double& ddp) {
  const double t2 = tau * tau, t3 = t2 * tau;
  p = t3 * (10.0 - 15.0 * tau + 6.0 * t2);
  dp = 30.0 * t2 * (1.0 - 2.0 * tau + t2);
  ddp = 60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2);
}

}  // namespace

bool ApproachPlannerOptions::validate(std::string& error) const {
  auto fail = [&](const std::string& m) {
    error = m;
    return false;
  };
  if (!(std::isfinite(duration_s) && duration_s > 0)) return fail("duration must be positive");
  if (!(std::isfinite(entry_radius_m) && entry_radius_m > 0))
    return fail("entry radius r_e must be positive");
  if (!(std::isfinite(exp_scale_m) && exp_scale_m > 0))
    return fail("exponential scale must be positive");
  if (!(s_e > 0 && s_e < 1)) return fail("s_e must lie in (0, 1) (eq. 5.16b)");
  if (!(s_a >= 0 && s_a < s_e)) return fail("s_a must lie in [0, s_e) (eq. 5.18)");
  if (!(std::isfinite(alpha_goal_rad) && std::isfinite(beta_goal_rad) &&
        std::isfinite(gamma_offset_rad)))
    return fail("goal angles must be finite");
  return true;
}

constexpr const char* kApproachStatusNames[] = {"ok", "start_inside_plant_circle",
                                                "fruit_outside_plant_circle", "start_too_far"};
const char* toString(ApproachStatus s) { return enumName(s, kApproachStatusNames); }

std::array<double, 6> quinticHermite(double p0, double v0, double a0, double p1, double v1,
                                     double a1) {
  const double d = p1 - p0;
  return {p0,
          v0,
          0.5 * a0,
          10.0 * d - 6.0 * v0 - 4.0 * v1 - 0.5 * (3.0 * a0 - a1),
          -15.0 * d + 8.0 * v0 + 7.0 * v1 + 0.5 * (3.0 * a0 - 2.0 * a1),
          6.0 * d - 3.0 * v0 - 3.0 * v1 - 0.5 * (a0 - a1)};
}

void evalPolynomial(const std::array<double, 6>& c, double u, double& p, double& dp, double& ddp) {
  p = c[5];
  dp = 5.0 * c[5];
  ddp = 20.0 * c[5];
  for (int k = 4; k >= 0; --k) {
    p = p * u + c[k];
    if (k >= 1) dp = dp * u + k * c[k];
    if (k >= 2) ddp = ddp * u + k * (k - 1) * c[k];
  }
}

ApproachTrajectory planApproach(const ApproachProblem& pb, const ApproachPlannerOptions& opt) {
  std::string err;
  ARMSTUDY_CHECK(opt.validate(err), "approach planner options: " + err);
  ApproachTrajectory tr;
  tr.opt_ = opt;
  tr.stem_ = pb.stem_xy_W;
  // eq. (5.15): stem frame rotated by delta, the angle of the stem seen from the reference point.
  const Eigen::Vector2d r_st = pb.stem_xy_W - pb.reference_xy_W;
  tr.delta_ = std::atan2(r_st.y(), r_st.x());
  const double c = std::cos(tr.delta_), s = std::sin(tr.delta_);
  const auto toStem = [&](const Eigen::Vector2d& p_W) {
    const Eigen::Vector2d d = p_W - pb.stem_xy_W;
    return Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  };
  // eq. (5.14): polar coordinates of start and goal.
  const Eigen::Vector2d xs = toStem(pb.p_start_W.head<2>()), xg = toStem(pb.fruit_W.head<2>());
  tr.start_.r = xs.norm();
  tr.start_.phi = polarAngle(xs.x(), xs.y());
  tr.r_g_ = xg.norm();
  tr.phi_g_ = polarAngle(xg.x(), xg.y());
  const double r_e = opt.entry_radius_m, L = opt.exp_scale_m;
  if (tr.start_.r <= r_e) {
    tr.status_ = ApproachStatus::StartInsidePlantCircle;
    return tr;
  }
  if (tr.r_g_ >= r_e) {
    tr.status_ = ApproachStatus::FruitOutsidePlantCircle;
    return tr;
  }
  // eq. (5.19) with the length scale L (the thesis has L = 1 m): r(0) = r_s, r(s_e) = r_e.
  tr.b_ = tr.start_.r - L;
  if (!(r_e - tr.b_ > 0)) {
    tr.status_ = ApproachStatus::StartTooFar;
    return tr;
  }
  tr.a_ = -std::log((r_e - tr.b_) / L) / opt.s_e;
  const double ea = L * std::exp(-tr.a_ * opt.s_e);
  tr.start_.dr = -tr.a_ * L;
  tr.start_.ddr = tr.a_ * tr.a_ * L;
  // eq. (5.20a-c): r_bar matches r, r', r'' of the exponential at s_e and comes to rest at r_g.
  const double du_r = 1.0 - opt.s_e;
  tr.r_coef_ =
      quinticHermite(r_e, -tr.a_ * ea * du_r, tr.a_ * tr.a_ * ea * du_r * du_r, tr.r_g_, 0, 0);
  // eq. (5.20d, e): phi_bar from phi_s at s_a to phi_g at s_e with zero slope and curvature.
  tr.phi_coef_ = quinticHermite(tr.start_.phi, 0, 0, tr.phi_g_, 0, 0);
  // Entry time t_e: s(t_e) = s_e on the monotone quintic (Newton, safeguarded by bisection).
  double lo = 0, hi = 1, tau = opt.s_e;
  for (int it = 0; it < defaults::kTimeScalingMaxIterations; ++it) {
    double p, dp, ddp;
    restToRest(tau, p, dp, ddp);
    const double f = p - opt.s_e;
    if (std::abs(f) < defaults::kTimeScalingNewtonTol) break;
    (f > 0 ? hi : lo) = tau;
    const double next = dp > 0 ? tau - f / dp : 0.5 * (lo + hi);
    tau = (next > lo && next < hi) ? next : 0.5 * (lo + hi);
  }
  tr.t_e_ = tau * opt.duration_s;
  // Height and orientation goals (section "Trajectory for the General Three Dimensional Case").
  tr.z_ab_start_ = Eigen::Vector3d(pb.p_start_W.z(), pb.cardan_start.x(), pb.cardan_start.y());
  tr.z_ab_goal_ = Eigen::Vector3d(pb.fruit_W.z(), opt.alpha_goal_rad, opt.beta_goal_rad);
  // gamma_g from phi_g and delta: heading of the radial approach (entry point towards the stem).
  const double heading = tr.phi_g_ + tr.delta_ + std::numbers::pi + opt.gamma_offset_rad;
  tr.gamma_s_ = pb.cardan_start.z();
  tr.cardan_g_ = Eigen::Vector3d(opt.alpha_goal_rad, opt.beta_goal_rad,
                                 tr.gamma_s_ + wrapToPi(heading - tr.gamma_s_));
  return tr;
}

Eigen::Vector2d ApproachTrajectory::entryPointXY() const {
  const double r = opt_.entry_radius_m, c = std::cos(delta_), s = std::sin(delta_);
  const Eigen::Vector2d x(r * std::cos(phi_g_), r * std::sin(phi_g_));
  return stem_ + Eigen::Vector2d(c * x.x() - s * x.y(), s * x.x() + c * x.y());
}

PolarSample ApproachTrajectory::polynomialBranches(double s) const {
  PolarSample p;
  const double du_r = 1.0 - opt_.s_e, du_p = opt_.s_e - opt_.s_a;
  evalPolynomial(r_coef_, (s - opt_.s_e) / du_r, p.r, p.dr, p.ddr);
  p.dr /= du_r;
  p.ddr /= du_r * du_r;
  evalPolynomial(phi_coef_, (s - opt_.s_a) / du_p, p.phi, p.dphi, p.ddphi);
  p.dphi /= du_p;
  p.ddphi /= du_p * du_p;
  return p;
}

PolarSample ApproachTrajectory::polar(double s) const {
  ARMSTUDY_CHECK(status_ == ApproachStatus::Ok,
                 "approach trajectory evaluated after a failed plan");
  s = std::clamp(s, 0.0, 1.0);
  const PolarSample poly = polynomialBranches(s);
  PolarSample p;
  if (s <= opt_.s_e) {
    // eq. (5.17), first branch.
    const double e = opt_.exp_scale_m * std::exp(-a_ * s);
    p.r = e + b_;
    p.dr = -a_ * e;
    p.ddr = a_ * a_ * e;
  } else {
    p.r = poly.r;
    p.dr = poly.dr;
    p.ddr = poly.ddr;
  }
  // eq. (5.18).
  if (s <= opt_.s_a) {
    p.phi = start_.phi;
  } else if (s <= opt_.s_e) {
    p.phi = poly.phi;
    p.dphi = poly.dphi;
    p.ddphi = poly.ddphi;
  } else {
    p.phi = phi_g_;
  }
  return p;
}

PathSample ApproachTrajectory::path(double s) const {
  PathSample out;
  const PolarSample& p = out.polar = polar(s);
  const double cp = std::cos(p.phi), sp = std::sin(p.phi);
  // Cartesian point in the stem frame and its s-derivatives (cf. eq. 5.22).
  const Eigen::Vector2d x(p.r * cp, p.r * sp);
  const Eigen::Vector2d dx(p.dr * cp - p.r * p.dphi * sp, p.dr * sp + p.r * p.dphi * cp);
  const double rad = p.ddr - p.r * p.dphi * p.dphi, tan = 2.0 * p.dr * p.dphi + p.r * p.ddphi;
  const Eigen::Vector2d ddx(rad * cp - tan * sp, rad * sp + tan * cp);
  // eq. (5.21), back to W (the inverse of the rotation A_st,0 of eq. 5.15b).
  Eigen::Matrix2d A_0st;
  A_0st << std::cos(delta_), -std::sin(delta_), std::sin(delta_), std::cos(delta_);
  out.xy = stem_ + A_0st * x;
  out.dxy = A_0st * dx;
  out.ddxy = A_0st * ddx;
  return out;
}

void ApproachTrajectory::timeScaling(double t, double& s, double& sd, double& sdd) const {
  const double T = opt_.duration_s;
  const double tau = std::clamp(t / T, 0.0, 1.0);
  restToRest(tau, s, sd, sdd);
  sd /= T;
  sdd /= T * T;
}

TaskSample ApproachTrajectory::sample(double t) const {
  TaskSample out;
  out.t = std::clamp(t, 0.0, opt_.duration_s);
  double s, sd, sdd;
  timeScaling(out.t, s, sd, sdd);
  out.s = s;
  const PathSample P = path(s);
  out.w.head<2>() = P.xy;
  out.wd.head<2>() = P.dxy * sd;
  out.wdd.head<2>() = P.ddxy * sd * sd + P.dxy * sdd;
  // eq. (5.23), (5.24): rest-to-rest quintic in time on [0, t_e], constant afterwards.
  double sig = 1, dsig = 0, ddsig = 0;
  if (out.t < t_e_) {
    restToRest(out.t / t_e_, sig, dsig, ddsig);
    dsig /= t_e_;
    ddsig /= t_e_ * t_e_;
  }
  const Eigen::Vector3d d = z_ab_goal_ - z_ab_start_;
  out.w[2] = z_ab_start_[0] + d[0] * sig;
  out.w[3] = z_ab_start_[1] + d[1] * sig;
  out.w[4] = z_ab_start_[2] + d[2] * sig;
  out.w[5] = gamma_s_ + (cardan_g_.z() - gamma_s_) * sig;
  const Eigen::Vector4d dd(d[0], d[1], d[2], cardan_g_.z() - gamma_s_);
  out.wd.tail<4>() = dd * dsig;
  out.wdd.tail<4>() = dd * ddsig;
  return out;
}

PoseReference poseReference(const TaskSample& w, const Eigen::Matrix3d& R_tool) {
  PoseReference r;
  r.p_WT = w.w.head<3>();
  r.v_W = w.wd.head<3>();
  r.a_W = w.wdd.head<3>();
  const double al = w.w[3], be = w.w[4], ga = w.w[5];
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(al, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(be, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(ga, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  r.R_WT = Rx * Ry * Rz * R_tool;
  // eq. (5.7): omega = e_x alpha_d + Rx e_y beta_d + Rx Ry e_z gamma_d (Cardan x-y-z).
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Rx.col(1), ez = (Rx * Ry).col(2);
  const double ad = w.wd[3], bd = w.wd[4], gd = w.wd[5];
  r.omega_W = ex * ad + ey * bd + ez * gd;
  // d/dt of the axes: ey rotates with alpha_d about ex; ez with the angular velocity of Rx Ry.
  const Eigen::Vector3d w_xy = ex * ad + ey * bd;
  r.omegad_W = ex * w.wdd[3] + ey * w.wdd[4] + ez * w.wdd[5] + (ex * ad).cross(ey) * bd +
               w_xy.cross(ez) * gd;
  return r;
}

}  // namespace armstudy
