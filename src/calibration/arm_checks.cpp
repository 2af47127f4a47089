#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "calibration/arm_engine.hpp"
#include "calibration/stats.hpp"
#include "common/format.hpp"

// The checks of the selection rule (docs/calibration.md "Selection rule"): the logging
// resolution of each channel and the floor, physically possible values, and the remainders a fit
// leaves.
namespace armstudy::calibration {

namespace arm_detail {

namespace {
constexpr double kFloorSteps = 4;  // a residual within 4 logging steps is at the floor
}  // namespace

// Per channel: the resolution and whether the design's residual is at that floor (RMS within
// kFloorSteps resolution steps); warned once per channel at the floor.
void floorOfChannels(const ArmProblem& P, const Eigen::MatrixXd& residual, ArmDiagnosis& d) {
  d.channel_resolution.assign(P.channels(), 0.0);
  d.channel_at_floor.assign(P.channels(), 0);
  for (int c = 0; c < P.channels(); ++c) {
    const double q = P.logged_resolution.empty()
                         ? loggingResolution(std::vector<double>(
                               P.measured.col(c).data(), P.measured.col(c).data() + P.rows()))
                         : P.logged_resolution[c];
    d.channel_resolution[c] = q;
    const double r = P.rows() ? std::sqrt(residual.col(c).squaredNorm() / P.rows()) : 0.0;
    if (q > 0 && r <= kFloorSteps * q) {
      d.channel_at_floor[c] = 1;
      d.warnings.push_back(
          "channel " + P.channel_names[c] + " is at the logging resolution (its values lie on " +
          "steps of " + formatG(q, 3) + " " + P.channel_units[c] + "; the design's residual is " +
          formatG(r, 3) + " " + P.channel_units[c] + " RMS, within " + formatG(kFloorSteps, 2) +
          " steps): not identifiable from these " + "logs, no effect is added for it");
    }
  }
}

const ArmPattern* strongestAboveFloor(const ArmProblem& P, const ArmDiagnosis& d) {
  for (const ArmPattern& p : d.patterns) {
    const auto& names = P.channel_names;
    const auto c = std::find(names.begin(), names.end(), p.channel) - names.begin();
    if (c >= static_cast<long>(d.channel_at_floor.size()) || !d.channel_at_floor[c]) return &p;
  }
  return nullptr;
}

// Why the fitted values describe no possible body or drive ("" when they do): a parameter on its
// physical lower bound (the value it would take without the bound is given: the bounded fit only
// stopped there), or a rigid body whose pseudo-inertia [[tr(I)/2 1 - I, h], [h^T, m]] is not
// positive semidefinite (Wensing et al. 2017: mass >= 0, inertia positive semidefinite about the
// centre and the triangle inequalities in one condition).
std::string impossibility(const ArmProblem& P, const ArmFit& fit) {
  const EffectValues& values = fit.values;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const ArmEffect& info = P.catalogue[values[k].effect];
    for (std::size_t j = 0; j < info.params.size(); ++j) {
      const ArmParam& ap = info.params[j];
      if (ap.physical.empty() || !std::isfinite(ap.lower)) continue;
      const double x = values[k].x[j];
      if (x > ap.lower + 1e-9 * (1 + std::abs(ap.lower)) + 1e-3 * ap.step) continue;
      // The value without the bound: the same set fitted with the physical bounds lifted.
      NoiseWeighted free(P, P.weight);
      for (ArmEffect& e : free.catalogue)
        for (ArmParam& q : e.params)
          if (!q.physical.empty()) q.lower = -kInf;
      const Solved s = fitSet(free, values);
      return info.name + "." + ap.key + " would be " + formatG(ap.design + s.v[k].x[j], 4) + " " +
             ap.unit + " (bound " + formatG(ap.design + ap.lower, 4) + "): " + ap.physical;
    }
    if (info.rigid_body && values[k].x.size() == 10) {
      Eigen::Matrix<double, 10, 1> pi;
      for (int i = 0; i < 10; ++i) pi[i] = info.body_design[i] + values[k].x[i];
      Eigen::Matrix3d I;
      I << pi[4], pi[7], pi[8], pi[7], pi[5], pi[9], pi[8], pi[9], pi[6];
      Eigen::Matrix4d J = Eigen::Matrix4d::Zero();
      J.topLeftCorner<3, 3>() = 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
      J.topRightCorner<3, 1>() = pi.segment<3>(1);
      J.bottomLeftCorner<1, 3>() = pi.segment<3>(1).transpose();
      J(3, 3) = pi[0];
      // Within its uncertainty of a possible body: a point mass lies on the cone's boundary, so
      // its fitted parameters leave it by the noise; the tolerance is the sum of the 95 %
      // half-widths of the inertia parameters.
      double tol = 1e-9 * (1 + J.norm());
      for (const FittedParameter& f : fit.params)
        if (f.key.rfind(info.name + ".inertia_", 0) == 0 && std::isfinite(f.ci_high - f.ci_low))
          tol += 0.5 * (f.ci_high - f.ci_low);
      const double ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J).eigenvalues()[0];
      if (ev < -tol)
        return info.name + " would be a body of mass " + formatG(pi[0], 4) + " kg, first moment (" +
               formatG(pi[1], 4) + ", " + formatG(pi[2], 4) + ", " + formatG(pi[3], 4) +
               ") kg m and inertia (xx yy zz) (" + formatG(pi[4], 4) + ", " + formatG(pi[5], 4) +
               ", " + formatG(pi[6], 4) + ") kg m^2: its pseudo-inertia has the eigenvalue " +
               formatG(ev, 4) + " < 0 beyond its uncertainty (" + formatG(tol, 4) +
               "): no physical body has these parameters";
    }
  }
  return "";
}

// Per channel, the strongest significant pattern of the final residuals as a remainder.
std::vector<ArmRemainder> remaindersOf(const ArmProblem& P, const ArmDiagnosis& d,
                                       const ArmFit& fin) {
  std::vector<ArmRemainder> out;
  const int R = P.rows();
  for (int c = 0; c < P.channels(); ++c) {
    const ArmPattern* best = nullptr;
    for (const ArmPattern& p : d.patterns)
      if (p.significant && p.channel == P.channel_names[c] &&
          (!best || p.sum_squares > best->sum_squares))
        best = &p;
    if (!best || R == 0 || fin.heldout_residual.rows() != R ||
        d.as_designed.heldout_residual.rows() != R)
      continue;
    ArmRemainder r;
    r.channel = best->channel;
    r.unit = P.channel_units[c];
    r.variable = best->variable;
    r.description = best->description;
    r.rms = d.channel_noise[c] * std::sqrt(best->sum_squares / R);
    const double ms_final = fin.heldout_residual.col(c).squaredNorm() / R,
                 ms_design = d.as_designed.heldout_residual.col(c).squaredNorm() / R;
    r.rmse_final = std::sqrt(ms_final);
    r.rmse_design = std::sqrt(ms_design);
    r.share_final = ms_final > 0 ? std::min(1.0, r.rms * r.rms / ms_final) : 0.0;
    r.share_design = ms_design > 0 ? std::min(1.0, r.rms * r.rms / ms_design) : 0.0;
    r.explained_by_catalogue = ms_final <= 0.25 * ms_design;
    out.push_back(r);
  }
  return out;
}

}  // namespace arm_detail

std::string ArmRemainder::text() const {
  return "unexplained remainder in " + channel + " following " + variable + ": " + formatG(rms, 3) +
         " " + unit + " RMS, " + formatG(100 * share_final, 3) +
         " % of the channel's remaining held-out mean square (" + formatG(100 * share_design, 3) +
         " % of the design's); the channel's held-out RMSE went " + formatG(rmse_design, 3) +
         " -> " + formatG(rmse_final, 3) + " " + unit +
         (explained_by_catalogue ? " with the catalogue effects" : "") + " (" + description + ")";
}

}  // namespace armstudy::calibration
