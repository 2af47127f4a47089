// The heuristic approach planner (thesis section 5.3.2) against its own specification: the path
// constraints of eq. (5.16) and boundary conditions of eq. (5.20) evaluated on the result, geometry
// (outside the plant circle before the entry point, a straight segment after it), central finite
// differences for every derivative, C2 continuity at the switching points, rest at both ends.
#include "trajectory/approach_planner.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <numbers>

#include "common/errors.hpp"
#include "io/approach_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::test;

namespace {

constexpr double kBoundaryTolerance = 1e-12;   // exact constraints evaluated numerically
constexpr double kLineTolerance = 1e-12;       // distance from the entry-fruit line [m]
constexpr double kTrajFdStep = 1e-5;           // central-difference step [s] or [-]
constexpr double kTrajFdTolerance = 1e-6;      // derivative vs central differences (relative)
constexpr double kContinuityStep = 1e-9;       // one-sided offset around switching points [s]
constexpr double kContinuityTolerance = 1e-6;  // jump of w, wd, wdd across a switching point

// Fig. 5.8 scene: stem at (0.43, 0.8), start at (0.55, 0.79); fruits 38 mm from the stem
// (Table 2.2).
ApproachProblem fig58Problem(double fruit_angle, double fruit_z = 0.9) {
  ApproachProblem pb;
  pb.p_start_W = Eigen::Vector3d(0.55, 0.79, 1.1);
  pb.cardan_start = Eigen::Vector3d(0.2, -0.1, 0.5);
  pb.stem_xy_W = Eigen::Vector2d(0.43, 0.8);
  pb.fruit_W = Eigen::Vector3d(0.43 + 0.038 * std::cos(fruit_angle),
                               0.8 + 0.038 * std::sin(fruit_angle), fruit_z);
  return pb;
}

ApproachPlannerOptions fig58Options() {
  ApproachPlannerOptions o;  // r_e = 0.1 m, s_a = 0.1, s_e = 0.8
  o.duration_s = 2.0;
  return o;
}

std::vector<ApproachProblem> scenes() {
  std::vector<ApproachProblem> v;
  for (int k = 0; k < 12; ++k)
    v.push_back(fig58Problem(k * std::numbers::pi / 6 + 0.05, 0.7 + 0.05 * k));
  // A start far from the plant, on the other side of the stem, and a different reference point.
  ApproachProblem far = fig58Problem(2.0);
  far.p_start_W = Eigen::Vector3d(0.1, 0.3, 0.6);
  v.push_back(far);
  ApproachProblem behind = fig58Problem(-1.0);
  behind.p_start_W = Eigen::Vector3d(0.5, 1.2, 1.0);
  behind.reference_xy_W = Eigen::Vector2d(0.2, -0.1);
  v.push_back(behind);
  return v;
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * std::numbers::pi); }

}  // namespace

TEST_CASE("approach path meets the constraints of eq. 5.16 and the boundary conditions of eq. 5.20",
          "[trajectory][planner]") {
  const ApproachPlannerOptions opt = fig58Options();
  for (const ApproachProblem& pb : scenes()) {
    const ApproachTrajectory tr = planApproach(pb, opt);
    REQUIRE(tr.status() == ApproachStatus::Ok);
    const double r_e = opt.entry_radius_m, L = opt.exp_scale_m, s_a = opt.s_a, s_e = opt.s_e;
    const double r_s = (pb.p_start_W.head<2>() - pb.stem_xy_W).norm();
    const double r_g = (pb.fruit_W.head<2>() - pb.stem_xy_W).norm();
    // eq. (5.16a-c) in Cartesian form: start, entry point (radius r_e on the fruit's ray), fruit.
    CHECK((tr.path(0).xy - pb.p_start_W.head<2>()).norm() < kBoundaryTolerance);
    CHECK((tr.path(1).xy - pb.fruit_W.head<2>()).norm() < kBoundaryTolerance);
    const Eigen::Vector2d entry = tr.path(s_e).xy;
    CHECK(std::abs((entry - pb.stem_xy_W).norm() - r_e) < kBoundaryTolerance);
    const Eigen::Vector2d u_fruit = (pb.fruit_W.head<2>() - pb.stem_xy_W).normalized();
    CHECK(((entry - pb.stem_xy_W).normalized() - u_fruit).norm() < kBoundaryTolerance);
    CHECK((entry - tr.entryPointXY()).norm() < kBoundaryTolerance);
    CHECK(std::abs(tr.polar(0).r - r_s) < kBoundaryTolerance);
    CHECK(std::abs(tr.polar(1).r - r_g) < kBoundaryTolerance);
    // eq. (5.19): a and b put the exponential through r_s at s = 0 and r_e at s = s_e.
    CHECK(std::abs(L + tr.b() - r_s) < kBoundaryTolerance);
    CHECK(std::abs(L * std::exp(-tr.a() * s_e) + tr.b() - r_e) < kBoundaryTolerance);
    // eq. (5.20a-c): r_bar joins the exponential with equal slope and curvature, rests at r_g.
    const double e = L * std::exp(-tr.a() * s_e);
    const PolarSample pe = tr.polynomialBranches(s_e), p1 = tr.polynomialBranches(1.0);
    CHECK(std::abs(pe.r - r_e) < kBoundaryTolerance);
    CHECK(std::abs(pe.dr - (-tr.a() * e)) < kBoundaryTolerance);
    CHECK(std::abs(pe.ddr - tr.a() * tr.a() * e) < kBoundaryTolerance);
    CHECK(std::abs(p1.r - r_g) < kBoundaryTolerance);
    CHECK(std::abs(p1.dr) < kBoundaryTolerance);
    CHECK(std::abs(p1.ddr) < kBoundaryTolerance);
    // eq. (5.20d, e): phi_bar from phi_s at s_a to phi_g at s_e with zero slope and curvature.
    const PolarSample pa = tr.polynomialBranches(s_a);
    CHECK(std::abs(pa.phi - tr.start().phi) < kBoundaryTolerance);
    CHECK(std::abs(pe.phi - tr.phiGoal()) < kBoundaryTolerance);
    for (const PolarSample* p : {&pa, &pe}) {
      CHECK(std::abs(p->dphi) < kBoundaryTolerance);
      CHECK(std::abs(p->ddphi) < kBoundaryTolerance);
    }
    // The polar angle of the start, seen from the stem, in the stem frame of eq. (5.15).
    const Eigen::Vector2d d = pb.p_start_W.head<2>() - pb.stem_xy_W;
    CHECK(std::abs(angleDiff(std::atan2(d.y(), d.x()) - tr.delta(), tr.start().phi)) <
          kBoundaryTolerance);
  }
}

TEST_CASE("approach path stays outside the plant circle until the entry point, then runs straight",
          "[trajectory][planner]") {
  const ApproachPlannerOptions opt = fig58Options();
  for (const ApproachProblem& pb : scenes()) {
    const ApproachTrajectory tr = planApproach(pb, opt);
    REQUIRE(tr.status() == ApproachStatus::Ok);
    const Eigen::Vector2d stem = pb.stem_xy_W, fruit = pb.fruit_W.head<2>();
    const Eigen::Vector2d entry = tr.entryPointXY();
    const Eigen::Vector2d seg = fruit - entry;
    const int N = 2000;
    for (int k = 0; k < N; ++k) {
      const double s = opt.s_e * k / N;  // s in [0, s_e)
      CHECK((tr.path(s).xy - stem).norm() > opt.entry_radius_m);
    }
    double last_progress = 0;
    for (int k = 0; k <= N; ++k) {
      const double s = opt.s_e + (1 - opt.s_e) * k / N;  // s in [s_e, 1]
      const Eigen::Vector2d p = tr.path(s).xy - entry;
      // On the line through entry point and fruit, between the two, moving towards the fruit.
      const double off_line = std::abs(seg.x() * p.y() - seg.y() * p.x()) / seg.norm();
      CHECK(off_line < kLineTolerance);
      const double progress = p.dot(seg) / seg.squaredNorm();
      CHECK(progress >= last_progress - kLineTolerance);
      CHECK(progress <= 1 + kLineTolerance);
      last_progress = progress;
    }
    // The angle sweep never crosses the far side of the plant (the wrap of eq. 5.14 at phi = 0).
    for (int k = 0; k <= N; ++k) {
      const double phi = tr.polar(static_cast<double>(k) / N).phi;
      CHECK(phi >= std::min(tr.start().phi, tr.phiGoal()) - kBoundaryTolerance);
      CHECK(phi <= std::max(tr.start().phi, tr.phiGoal()) + kBoundaryTolerance);
    }
  }
}

TEST_CASE("path and trajectory derivatives match central finite differences", "[trajectory][fd]") {
  const ApproachPlannerOptions opt = fig58Options();
  for (const ApproachProblem& pb : scenes()) {
    const ApproachTrajectory tr = planApproach(pb, opt);
    REQUIRE(tr.status() == ApproachStatus::Ok);
    const double h = kTrajFdStep;
    // Half-step grid: central differences of a C2 (not C3) path are only O(h) accurate exactly at
    // the switching points s_a and s_e; continuity there is checked separately.
    for (int k = 0; k < 200; ++k) {
      const double s = (k + 0.5) / 200.0;
      INFO("s = " << s);
      const PathSample p = tr.path(s), pp = tr.path(s + h), pm = tr.path(s - h);
      const Eigen::Vector2d fd1 = (pp.xy - pm.xy) / (2 * h), fd2 = (pp.dxy - pm.dxy) / (2 * h);
      CHECK((fd1 - p.dxy).norm() < kTrajFdTolerance * std::max(1.0, p.dxy.norm()));
      CHECK((fd2 - p.ddxy).norm() < kTrajFdTolerance * std::max(1.0, p.ddxy.norm()));
    }
    for (int k = 1; k < 400; ++k) {
      const double t = opt.duration_s * k / 400.0;
      const TaskSample w = tr.sample(t), wp = tr.sample(t + h), wm = tr.sample(t - h);
      const Eigen::Matrix<double, 6, 1> fd1 = (wp.w - wm.w) / (2 * h),
                                        fd2 = (wp.wd - wm.wd) / (2 * h);
      INFO("t = " << t);
      CHECK((fd1 - w.wd).cwiseAbs().maxCoeff() <
            kTrajFdTolerance * std::max(1.0, w.wd.cwiseAbs().maxCoeff()));
      CHECK((fd2 - w.wdd).cwiseAbs().maxCoeff() <
            kTrajFdTolerance * std::max(1.0, w.wdd.cwiseAbs().maxCoeff()));
    }
  }
}

TEST_CASE("trajectory is C2 at its switching points and at rest at both ends",
          "[trajectory][planner]") {
  const ApproachPlannerOptions opt = fig58Options();
  for (const ApproachProblem& pb : scenes()) {
    const ApproachTrajectory tr = planApproach(pb, opt);
    REQUIRE(tr.status() == ApproachStatus::Ok);
    // Times where s(t) = s_a and s(t) = s_e (bisection on the monotone time scaling), and t_e.
    auto timeOf = [&](double s_target) {
      double lo = 0, hi = opt.duration_s;
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        double s, sd, sdd;
        tr.timeScaling(mid, s, sd, sdd);
        (s < s_target ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    };
    const double t_a = timeOf(opt.s_a), t_e = timeOf(opt.s_e);
    CHECK(std::abs(t_e - tr.entryTime()) < kBoundaryTolerance * opt.duration_s);
    for (double tb : {t_a, t_e}) {
      const TaskSample lo = tr.sample(tb - kContinuityStep), hi = tr.sample(tb + kContinuityStep);
      CHECK((lo.w - hi.w).cwiseAbs().maxCoeff() < kContinuityTolerance);
      CHECK((lo.wd - hi.wd).cwiseAbs().maxCoeff() < kContinuityTolerance);
      CHECK((lo.wdd - hi.wdd).cwiseAbs().maxCoeff() < kContinuityTolerance);
    }
    for (double t : {0.0, opt.duration_s}) {
      const TaskSample w = tr.sample(t);
      CHECK(w.wd.cwiseAbs().maxCoeff() < kBoundaryTolerance);
      CHECK(w.wdd.cwiseAbs().maxCoeff() < kBoundaryTolerance);
    }
    // Start pose, and the goal height and orientation reached at the entry time (eq. 5.23, 5.24).
    const TaskSample w0 = tr.sample(0), we = tr.sample(tr.entryTime()),
                     wT = tr.sample(opt.duration_s);
    CHECK((w0.w.head<3>() - pb.p_start_W).norm() < kBoundaryTolerance);
    CHECK((w0.w.tail<3>() - pb.cardan_start).norm() < kBoundaryTolerance);
    CHECK(std::abs(we.w[2] - pb.fruit_W.z()) < kBoundaryTolerance);
    CHECK((we.w.tail<3>() - tr.goalCardan()).norm() < kBoundaryTolerance);
    CHECK((wT.w.head<3>() - pb.fruit_W).norm() < kBoundaryTolerance);
    // The goal gamma points along the radial approach: entry point towards the fruit and stem.
    const Eigen::Vector2d approach = (pb.fruit_W.head<2>() - tr.entryPointXY()).normalized();
    CHECK(std::abs(angleDiff(tr.goalCardan().z(), std::atan2(approach.y(), approach.x()))) <
          kBoundaryTolerance);
    CHECK(std::abs(tr.goalCardan().z() - pb.cardan_start.z()) <=
          std::numbers::pi + kBoundaryTolerance);
    // Height and angles move monotonically (no overshoot, cf. eq. 5.25).
    double prev = w0.w[2];
    const double dir = pb.fruit_W.z() - pb.p_start_W.z();
    for (int k = 1; k <= 200; ++k) {
      const double z = tr.sample(tr.entryTime() * k / 200).w[2];
      CHECK((z - prev) * dir >= -kBoundaryTolerance);
      prev = z;
    }
  }
}

TEST_CASE("approach planner reports impossible geometry as a status", "[trajectory][planner]") {
  ApproachPlannerOptions opt = fig58Options();
  ApproachProblem inside = fig58Problem(1.0);
  inside.p_start_W.head<2>() = inside.stem_xy_W + Eigen::Vector2d(0.05, 0.0);
  CHECK(planApproach(inside, opt).status() == ApproachStatus::StartInsidePlantCircle);
  ApproachProblem outside = fig58Problem(1.0);
  outside.fruit_W.head<2>() = outside.stem_xy_W + Eigen::Vector2d(0.0, 0.15);
  CHECK(planApproach(outside, opt).status() == ApproachStatus::FruitOutsidePlantCircle);
  ApproachProblem far = fig58Problem(1.0);
  far.p_start_W.head<2>() = far.stem_xy_W + Eigen::Vector2d(-1.5, 0.0);
  CHECK(planApproach(far, opt).status() == ApproachStatus::StartTooFar);
  opt.exp_scale_m = 2.0;  // a larger length scale of eq. (5.17) admits it
  CHECK(planApproach(far, opt).status() == ApproachStatus::Ok);
}

TEST_CASE("bad approach settings are input errors naming file, line and key",
          "[trajectory][input]") {
  auto expectError = [](const std::string& body, const std::string& key) {
    try {
      (void)parseApproachOptions("# study\n[approach]\n" + body, "study.toml");
      FAIL("no InputError for " << key);
    } catch (const InputError& e) {
      CHECK(e.file() == "study.toml");
      CHECK(e.line() >= 2);
      CHECK(e.key() == key);
    }
  };
  expectError("duration = 0\n", "approach.duration");
  expectError("duration = -1.5\n", "approach.duration");
  expectError("s_a = 0.1\n", "approach.duration");  // missing
  expectError("duration = 2\ns_e = 1.0\n", "approach.s_e");
  expectError("duration = 2\ns_a = 0.8\ns_e = 0.8\n", "approach.s_a");
  expectError("duration = 2\nentry_radius = \"-10 mm\"\n", "approach.entry_radius");
  expectError("duration = 2\nentry_radius = \"10 deg\"\n", "approach.entry_radius");
  expectError("duration = 2\nexp_scale = 0\n", "approach.exp_scale");
  expectError("duration = 2\nspeed = 3\n", "approach.speed");  // unknown key
  const ApproachPlannerOptions o = parseApproachOptions(
      "[approach]\nentry_radius = \"100 mm\"\ns_a = 0.1\ns_e = 0.8\nduration = 2.5\n"
      "gamma_offset = \"90 deg\"\n",
      "ok.toml");
  CHECK(o.entry_radius_m == Approx(0.1).epsilon(1e-15));
  CHECK(o.duration_s == 2.5);
  CHECK(o.gamma_offset_rad == Approx(std::numbers::pi / 2).epsilon(1e-15));
}

TEST_CASE("pose reference: angular velocity and acceleration match finite differences of R_WT",
          "[trajectory][fd]") {
  const ApproachPlannerOptions opt = fig58Options();
  const Eigen::Matrix3d R_tool =
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (const ApproachProblem& pb : scenes()) {
    const ApproachTrajectory tr = planApproach(pb, opt);
    REQUIRE(tr.status() == ApproachStatus::Ok);
    const double h = kTrajFdStep;
    for (int k = 0; k < 100; ++k) {
      const double t = opt.duration_s * (k + 0.5) / 100;
      const PoseReference r = poseReference(tr.sample(t), R_tool);
      const PoseReference rp = poseReference(tr.sample(t + h), R_tool);
      const PoseReference rm = poseReference(tr.sample(t - h), R_tool);
      const Eigen::AngleAxisd aa(rp.R_WT * rm.R_WT.transpose());
      const Eigen::Vector3d omega_fd = aa.angle() * aa.axis() / (2 * h);
      CHECK((omega_fd - r.omega_W).norm() < kTrajFdTolerance * std::max(1.0, r.omega_W.norm()));
      const Eigen::Vector3d omegad_fd = (rp.omega_W - rm.omega_W) / (2 * h);
      CHECK((omegad_fd - r.omegad_W).norm() < kTrajFdTolerance * std::max(1.0, r.omegad_W.norm()));
      CHECK(((rp.p_WT - rm.p_WT) / (2 * h) - r.v_W).norm() < kTrajFdTolerance);
      CHECK((r.R_WT.transpose() * r.R_WT - Eigen::Matrix3d::Identity()).norm() <
            kBoundaryTolerance);
    }
    // With the tool z axis as approach axis (R_tool = Ry(pi/2)) the tool points horizontally from
    // the entry point towards the fruit at the end.
    const PoseReference end = poseReference(tr.sample(opt.duration_s), R_tool);
    const Eigen::Vector2d approach = (pb.fruit_W.head<2>() - tr.entryPointXY()).normalized();
    CHECK((end.R_WT.col(2) - Eigen::Vector3d(approach.x(), approach.y(), 0)).norm() <
          kBoundaryTolerance);
  }
}
