#include "calibration/arm_view.hpp"

#include <algorithm>
#include <cmath>

#include "common/format.hpp"
#include "study/scene.hpp"

namespace armstudy::calibration {

namespace {

constexpr double kViewPointSize = 0.01;  // [m] drawn size of a data row's point

// Whether row i's TCP position lies in a flagged workspace cell of `map` (the engine's binning: a
// cell holds [lo, hi), the last one along an axis also its upper edge).
bool inFlaggedCell(const ArmResidualMap& map, const Eigen::Vector3d& p) {
  for (const ArmBin& b : map.bins) {
    if (b.space != "workspace" || !b.flagged) continue;
    bool in = true;
    for (int a = 0; a < 3 && in; ++a) {
      const bool last = b.index[a] == map.ws_dims[a] - 1, first = b.index[a] == 0;
      in = (first || p[a] >= b.lo[a]) && (last || p[a] < b.hi[a]);
    }
    if (in) return true;
  }
  return false;
}

// The joint positions of row i: the operating variables that are joint positions, in joint order.
Eigen::VectorXd rowQ(const ArmProblem& P, int i, int dof) {
  Eigen::VectorXd q(dof);
  int j = 0;
  for (const BinVariable& v : P.variables)
    if (v.position && j < dof) q[j++] = v.values[i];
  return j == dof ? q : Eigen::VectorXd();
}

struct CloudSpec {
  std::string name, quantity, unit;
  std::vector<double> value;  // per row
};

report::ViewCloud cloudOf(const CloudSpec& s, const ArmProblem& P, const ArmResidualMap& map,
                          const Model& model) {
  report::ViewCloud c;
  c.name = s.name;
  c.value_quantity = s.quantity;
  c.value_unit = s.unit;
  c.point_size_m = kViewPointSize;
  c.status_names = {"in a flagged workspace cell (mean residual over its threshold)",
                    "in a workspace cell within its thresholds"};
  int worst = -1;
  for (int i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d& p = P.workspace[i];
    c.p_W.push_back({p.x(), p.y(), p.z()});
    c.status.push_back(inFlaggedCell(map, p) ? 0 : 1);
    c.value.push_back(s.value[i]);
    if (std::isfinite(s.value[i]) && (worst < 0 || s.value[i] > s.value[worst])) worst = i;
  }
  const Eigen::VectorXd q = worst < 0 ? Eigen::VectorXd() : rowQ(P, worst, model.dof());
  if (q.size() > 0) {
    for (const Eigen::Vector3d& x : scene::skeletonPoints(model, q))
      c.arm_W.push_back({x.x(), x.y(), x.z()});
    c.arm_caption = "arm: " + model.name + " at the data row of the largest residual (line " +
                    std::to_string(P.lines.empty() ? worst + 1 : P.lines[worst]) + ": " +
                    formatG(s.value[worst], 3) + " " + s.unit + ").";
  }
  return c;
}

}  // namespace

std::vector<report::ViewCloud> residualViewClouds(const ArmDiagnosis& d, const ArmProblem& P,
                                                  const Model& model, const std::string& entry) {
  std::vector<report::ViewCloud> out;
  if (P.workspace.size() != static_cast<std::size_t>(P.rows()) || P.rows() == 0) return out;
  const bool tcp = P.position_channels;
  std::vector<std::pair<const ArmFit*, const ArmResidualMap*>> models{
      {&d.as_designed, &d.as_designed_map}};
  if (!d.added.empty()) models.emplace_back(&d.final_fit, &d.final_map);
  for (std::size_t k = 0; k < models.size(); ++k) {
    const ArmFit& f = *models[k].first;
    const std::string when = k == 0 ? "before the fit" : "after the fit";
    if (tcp) {  // the position error's length, in mm
      CloudSpec s{entry + " " + when + ": TCP position error", "TCP position error", "mm", {}};
      for (int i = 0; i < P.rows(); ++i)
        s.value.push_back(1e3 * f.residual.row(i).head<3>().norm());
      out.push_back(cloudOf(s, P, *models[k].second, model));
      continue;
    }
    for (int ch = 0; ch < P.channels(); ++ch) {
      const std::string& name = P.channel_names[ch];
      CloudSpec s{entry + " " + when + ": " + name,
                  "|measured - predicted| of " + name,
                  P.channel_units[ch],
                  {}};
      for (int i = 0; i < P.rows(); ++i) s.value.push_back(std::abs(f.residual(i, ch)));
      out.push_back(cloudOf(s, P, *models[k].second, model));
    }
  }
  return out;
}

}  // namespace armstudy::calibration
