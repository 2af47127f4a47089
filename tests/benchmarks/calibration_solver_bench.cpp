// Bounded nonlinear least squares of the calibration engine ("One engine"): the in-house
// solver (Gauss-Newton, each step the bounded linear least squares of least_squares.hpp) against
// Ceres (Levenberg-Marquardt trust region, dense QR, parameter bounds, central-difference
// Jacobians of the same prediction), and the engine's linearised covariance against
// ceres::Covariance. Same problems, same start (zero change to the design), same residuals.
//   cmake --build build --target calibration_solver_bench &&
//   ./build/tests/benchmarks/calibration_solver_bench
// Prints, per problem: final SSR of both, the largest parameter difference relative to the
// parameter's 95 % interval half-width, the time per fit and the ratio Ceres / in-house.
#include <ceres/ceres.h>
#include <time.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "calibration/arm_calibration.hpp"
#include "calibration/drive_calibration.hpp"
#include "calibration/tcp_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "io/design_io.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::calibration;

namespace {

// CPU time of this thread per call [s], median of `batches` (the machine is shared: wall time
// would count other processes).
template <class Fn>
double cpuPerCall(Fn&& fn, int iters, int batches = 5) {
  std::vector<double> t;
  for (int b = 0; b < batches; ++b) {
    timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    for (int i = 0; i < iters; ++i) fn(i);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    t.push_back(((t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec)) / iters);
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

std::string src(const std::string& rel) { return armstudy::test::sourcePath(rel); }

// Residuals of the problem for a packed parameter vector (the profiled values stay as given).
struct Residuals {
  const ArmProblem* P;
  EffectValues shape;
  int n = 0;
  EffectValues unpack(const double* x) const {
    EffectValues v = shape;
    int k = 0;
    for (auto& e : v)
      for (int j = 0; j < e.x.size(); ++j) e.x[j] = x[k++];
    return v;
  }
  bool operator()(double const* const* params, double* r) const {
    const Eigen::MatrixXd pred = P->predict(unpack(params[0]));
    for (int i = 0; i < P->rows(); ++i)
      for (int c = 0; c < P->channels(); ++c)
        r[i * P->channels() + c] = (P->measured(i, c) - pred(i, c)) * P->weight[c];
    return true;
  }
};

struct CeresFit {
  std::vector<double> x;
  double ssr = 0;
  std::vector<double> sd;  // standard deviations from ceres::Covariance (unscaled: J^T J inverse)
  int iterations = 0;
};

// Solves from `start` (solve) or only evaluates the covariance at `start` (covariance, no solve).
CeresFit ceresFit(const ArmProblem& P, const EffectValues& start, bool covariance,
                  bool solve = true) {
  Residuals f{&P, start, 0};
  for (const auto& e : start) f.n += static_cast<int>(e.x.size());
  CeresFit out;
  out.x.assign(f.n, 0.0);
  for (int k = 0, a = 0; a < static_cast<int>(start.size()); ++a)
    for (int j = 0; j < start[a].x.size(); ++j) out.x[k++] = start[a].x[j];
  auto* cost =
      new ceres::DynamicNumericDiffCostFunction<Residuals, ceres::CENTRAL>(new Residuals(f));
  cost->AddParameterBlock(f.n);
  cost->SetNumResiduals(P.rows() * P.channels());
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, out.x.data());
  for (int k = 0, a = 0; a < static_cast<int>(start.size()); ++a)
    for (const ArmParam& p : P.catalogue[start[a].effect].params) {
      if (std::isfinite(p.lower)) problem.SetParameterLowerBound(out.x.data(), k, p.lower);
      if (std::isfinite(p.upper)) problem.SetParameterUpperBound(out.x.data(), k, p.upper);
      ++k;
    }
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.function_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.gradient_tolerance = 1e-14;
  o.max_num_iterations = 100;
  o.logging_type = ceres::SILENT;
  if (solve) {
    ceres::Solver::Summary s;
    ceres::Solve(o, &problem, &s);
    out.ssr = 2 * s.final_cost;
    out.iterations = static_cast<int>(s.iterations.size());
  }
  if (covariance) {
    ceres::Covariance::Options co;
    ceres::Covariance cov(co);
    std::vector<std::pair<const double*, const double*>> blocks = {{out.x.data(), out.x.data()}};
    if (cov.Compute(blocks, &problem)) {
      std::vector<double> c(f.n * f.n);
      cov.GetCovarianceBlock(out.x.data(), out.x.data(), c.data());
      for (int j = 0; j < f.n; ++j) out.sd.push_back(std::sqrt(c[j * f.n + j]));
    }
  }
  return out;
}

// The engine's intervals without the AR(1) inflation and s^2: sqrt(diag((J^T J)^-1)), J by
// central differences as in the engine (for comparing with ceres::Covariance, also unscaled).
std::vector<double> engineSd(const ArmProblem& P, const EffectValues& v) {
  Residuals f{&P, v, 0};
  std::vector<double> x;
  for (const auto& e : v)
    for (int j = 0; j < e.x.size(); ++j) x.push_back(e.x[j]);
  const int n = static_cast<int>(x.size()), N = P.rows() * P.channels();
  Eigen::MatrixXd J(N, n);
  std::vector<double> rp(N), rm(N);
  int k = 0;
  for (const auto& e : v)
    for (const ArmParam& p : P.catalogue[e.effect].params) {
      std::vector<double> xp = x, xm = x;
      xp[k] += p.step;
      xm[k] -= p.step;
      const double* a = xp.data();
      const double* b = xm.data();
      f(&a, rp.data());
      f(&b, rm.data());
      for (int i = 0; i < N; ++i) J(i, k) = -(rp[i] - rm[i]) / (2 * p.step);
      ++k;
    }
  const Eigen::MatrixXd C = (J.transpose() * J).inverse();
  std::vector<double> sd;
  for (int j = 0; j < n; ++j) sd.push_back(std::sqrt(C(j, j)));
  return sd;
}

struct Case {
  std::string name;
  std::shared_ptr<ArmProblem> P;
  EffectValues start;
  int iters;
};

EffectValue zeroOf(const ArmProblem& P, const std::string& name, double profile = 0) {
  EffectValue v;
  v.effect = P.findEffect(name);
  if (v.effect < 0) throw std::runtime_error("no effect " + name);
  v.x = Eigen::VectorXd::Zero(P.catalogue[v.effect].params.size());
  v.profile = profile;
  return v;
}

void run(const Case& c) {
  const ArmProblem& P = *c.P;
  SetFit mine;
  CeresFit theirs;
  const double t_mine = cpuPerCall([&](int) { mine = fitEffects(P, c.start); }, c.iters);
  const double t_ceres = cpuPerCall([&](int) { theirs = ceresFit(P, c.start, false); }, c.iters);
  // Parameter agreement in units of the engine's standard deviation (noise-free: sd of J^T J).
  const std::vector<double> sd = engineSd(P, mine.values);
  const double s =
      std::sqrt(mine.ssr / std::max(1, P.rows() * P.channels() - static_cast<int>(sd.size())));
  double worst = 0;
  int k = 0;
  for (const auto& e : mine.values)
    for (int j = 0; j < e.x.size(); ++j, ++k)
      worst = std::max(worst, std::abs(e.x[j] - theirs.x[k]) / (s * sd[k]));
  // Covariance at the engine's optimum: the engine's (J^T J)^-1 against ceres::Covariance.
  const double t_cov_mine =
      cpuPerCall([&](int) { bench::doNotOptimize(engineSd(P, mine.values)[0]); }, c.iters);
  CeresFit withCov;
  const double t_cov_ceres =
      cpuPerCall([&](int) { withCov = ceresFit(P, mine.values, true, false); }, c.iters);
  double cov_rel = 0;
  for (std::size_t j = 0; j < sd.size() && j < withCov.sd.size(); ++j)
    cov_rel = std::max(cov_rel, std::abs(withCov.sd[j] - sd[j]) / sd[j]);
  std::printf("%-48s %3d %11.6g %11.6g %9.2e %9.3g %9.3g %6.1f %9.2e %6.1f\n", c.name.c_str(), k,
              mine.ssr, theirs.ssr, worst, 1e3 * t_mine, 1e3 * t_ceres, t_ceres / t_mine, cov_rel,
              t_cov_ceres / t_cov_mine);
}

}  // namespace

int main() {
  const Model d9 = loadDesign(src("designs/final_prototype_9dof.toml"));
  const Model d7 = loadDesign(src("designs/final_prototype_7dof.toml"));
  std::vector<Case> cases;
  {  // Thesis chapter 4: refit eq. 3.30 + Stribeck at the fitted v_S, the B.2 sample (linear).
    const DriveData data = readDriveData(src("studies/data/drive_testbed_module_b2.csv"));
    std::shared_ptr<ArmProblem> P = makeDriveProblem(d9, "j6", data);
    cases.push_back({"drive B.2: refit + stribeck (v_S 64.1)",
                     P,
                     {zeroOf(*P, kRefitEffect), zeroOf(*P, "stribeck", 64.12)},
                     50});
    // The same with an active bound: Coulomb friction capped at 0.12 N m (fit: 0.135).
    std::shared_ptr<ArmProblem> Q = makeDriveProblem(d9, "j6", data);
    ArmParam& c = Q->catalogue[Q->findEffect(kRefitEffect)].params[0];
    c.upper = 0.12 - c.design;
    cases.push_back({"drive B.2: same, coulomb <= 0.12 (bound active)",
                     Q,
                     {zeroOf(*Q, kRefitEffect), zeroOf(*Q, "stribeck", 64.12)},
                     50});
  }
  {  // tcp: a joint offset and a link length from zero (nonlinear kinematics), 60 poses.
    TcpSynthOptions so;
    so.rows = 60;
    so.noise_m = 2e-4;
    so.seed = 1;
    so.hidden = {"joint_offset.j3:offset=0.01", "link_length.j4.x:dx=0.005"};
    std::shared_ptr<ArmProblem> P = makeTcpProblem(d7, synthesizeTcp(d7, so));
    cases.push_back({"tcp 7-DoF: joint_offset.j3 + link_length.j4.x",
                     P,
                     {zeroOf(*P, "joint_offset.j3"), zeroOf(*P, "link_length.j4.x")},
                     20});
  }
  {  // trajectory: a payload from zero (10 linear inertial parameters), 3 s at 40 Hz.
    TrajectorySynthOptions so;
    so.duration_s = 3;
    so.rate_Hz = 40;
    so.noise = 0.05;
    so.seed = 1;
    so.hidden = {"payload"};
    std::shared_ptr<ArmProblem> P = makeTrajectoryProblem(d7, synthesizeTrajectory(d7, so));
    cases.push_back({"trajectory 7-DoF: payload (10 parameters)", P, {zeroOf(*P, "payload")}, 3});
  }
  std::printf(
      "CPU time per fit (this thread), median of 5 batches; |dx|/sd: largest parameter difference "
      "in\n"
      "standard deviations; cov rel: largest relative difference of the standard deviations;\n"
      "ratios are Ceres / engine (fit, covariance).\n");
  std::printf("%-48s %3s %11s %11s %9s %9s %9s %6s %9s %6s\n", "problem", "p", "SSR engine",
              "SSR Ceres", "|dx|/sd", "engine ms", "Ceres ms", "ratio", "cov rel", "cov r.");
  for (const Case& c : cases) run(c);
  return 0;
}
