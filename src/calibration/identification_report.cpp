#include "calibration/identification_report.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "common/defaults.hpp"
#include "common/format.hpp"
#include "dynamics/dynamics.hpp"
#include "report/markdown.hpp"
#include "report/plot.hpp"

namespace armstudy::calibration {

namespace {

// Time-block held-out RMSE of every channel along the ladder, and the factor first / last.
std::string ladderSection(const ArmDiagnosis& d, const ArmProblem& P,
                          std::vector<std::pair<std::string, double>>& M) {
  std::vector<std::string> head = {"model", ">params"};
  for (int c = 0; c < P.channels(); ++c)
    head.push_back(">" + P.channel_names[c] + " [" + P.channel_units[c] + "]");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < d.ladder.size(); ++k) {
    const ArmFit& f = d.ladder[k];
    std::vector<std::string> row = {f.label, std::to_string(f.n_params)};
    for (int c = 0; c < P.channels(); ++c) {
      const double v = c < static_cast<int>(f.channel_region_heldout.size())
                           ? f.channel_region_heldout[c].rmse
                           : NAN;
      row.push_back(formatGOr(v, 4, "-"));
      M.emplace_back("ladder/" + std::to_string(k) + "/" + P.channel_names[c], v);
    }
    rows.push_back(row);
  }
  std::vector<std::string> factor = {"factor first / last", ""};
  const ArmFit &a = d.ladder.front(), &b = d.ladder.back();
  for (int c = 0; c < P.channels(); ++c) {
    const bool ok = c < static_cast<int>(a.channel_region_heldout.size()) &&
                    c < static_cast<int>(b.channel_region_heldout.size());
    const double f = ok ? a.channel_region_heldout[c].rmse / b.channel_region_heldout[c].rmse : NAN;
    factor.push_back(formatGOr(f, 4, "-"));
    M.emplace_back("factor/" + P.channel_names[c], f);
  }
  rows.push_back(factor);
  std::ostringstream md;
  md << "## Error ladder per joint\n\nRMSE of each joint's effort, held out by time block (the fit "
        "on the other "
     << P.region_count
     << " - 1 blocks predicts the block left out), for every step of the ladder.\n\n"
     << report::markdownTable(head, rows) << "\n";
  return md.str();
}

bool ofJoint(const std::string& effect, const std::string& joint) {
  return effect.rfind(joint + ".", 0) == 0 || effect.rfind("motor_" + joint + ".", 0) == 0;
}

// Per joint: its candidates in the order of the first ranking (the design as is), and the effects
// the ladder added, in that order.
std::string orderSection(const ArmDiagnosis& d, const Model& model,
                         std::vector<std::pair<std::string, double>>& M) {
  std::ostringstream md;
  md << "## Missing effects per joint\n\nRanked: the joint's candidates in the order of the first "
        "ranking (the "
        "design as is; held-out improvement in its channel, * significant). Added: the order the "
        "ladder added them.\n\n";
  std::vector<std::vector<std::string>> rows;
  for (const auto& j : model.joints) {
    std::string ranked, added;
    int k = 0;
    for (const ArmCandidate& c : d.ranking) {
      if (!ofJoint(c.name, j.name) || c.status != "ok") continue;
      const std::string shown =
          c.name.rfind("motor_", 0) == 0 ? c.name : c.name.substr(c.name.find('.') + 1);
      if (k < 4)
        ranked += (ranked.empty() ? "" : ", ") + shown + " (" +
                  report::fixed(100 * c.improvement, 1) + " %" + (c.significant ? "*" : "") + ")";
      M.emplace_back("first_ranking/" + j.name + "/" + shown, ++k);
    }
    for (const std::string& a : d.added)
      if (ofJoint(a, j.name)) added += (added.empty() ? "" : ", ") + a;
    rows.push_back({j.name, ranked, added.empty() ? "none" : added});
  }
  md << report::markdownTable({"joint", "ranked", "added"}, rows) << "\n";
  return md.str();
}

// The final effects plus every effect with a reference value (fitted together).
EffectValues withReferenced(const ArmProblem& P, const EffectValues& final_values,
                            const IdentificationInput& in) {
  EffectValues v = final_values;
  for (const auto& [name, value] : in.reference) {
    const int e = P.findEffect(name);
    if (e < 0 || findValue(v, e)) continue;
    EffectValue x;
    x.effect = e;
    x.x = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(P.catalogue[e].params.size()));
    v.push_back(x);
  }
  return v;
}

double firstParam(const EffectValues& v, int e) {
  const EffectValue* x = findValue(v, e);
  return x ? x->x[0] : std::numeric_limits<double>::quiet_NaN();
}

// What a joint-side reference value compares with: the coefficient of the joint's own speed
// (viscous) or acceleration (armature) in its own channel. A motor that turns several joints (a
// row k of the coupling matrix R with more than one entry) adds its term there reflected twice
// through r = R_kj / R_kk (its speed carries r qd_j, its torque reaches joint j as r times the
// term): the joint's own term plus r^2 times the motor's. The motor's own terms are the coupling
// coefficients (the cross terms, qd_j in another joint's channel) and compare as they are, as do
// the Coulomb terms (not linear in the speed) and every joint no coupled motor turns.
struct Compared {
  double value = NAN;
  std::string how;  // "" when the term compares as it is
};
Compared jointSide(const ArmProblem& P, const Model& model, const TrajectoryData& data,
                   const EffectValues& v, int e) {
  const ArmEffect& info = P.catalogue[e];
  Compared out{firstParam(v, e), ""};
  const std::string motor_term = info.effect == "viscous"    ? "viscous"
                                 : info.effect == "armature" ? "inertia"
                                                             : "";
  const int n = model.dof(), j = model.jointIndex(info.joint);
  if (motor_term.empty() || j < 0 || data.coupling.rows() != n || !std::isfinite(out.value))
    return out;
  std::string parts;
  for (int k = 0; k < n; ++k) {
    const int m = P.findEffect("motor_" + model.joints[k].name + "." + motor_term);
    const double x = m >= 0 ? firstParam(v, m) : NAN;
    if (!std::isfinite(x) || data.coupling(k, k) == 0 || data.coupling(k, j) == 0) continue;
    const double r2 = std::pow(data.coupling(k, j) / data.coupling(k, k), 2);
    out.value += r2 * x;
    parts += " + " + (r2 == 1 ? std::string() : formatGOr(r2, 4, "-") + " x ") +
             P.catalogue[m].name + " " + formatGOr(x, 4, "-");
  }
  if (!parts.empty()) out.how = info.name + " " + formatGOr(firstParam(v, e), 4, "-") + parts;
  return out;
}

// Flattened (row-major) column of a rows x channels change, each channel weighted by 1 / its
// noise, as the fit weighs it.
Eigen::VectorXd weighted(const Eigen::MatrixXd& m, const std::vector<double>& noise) {
  Eigen::VectorXd v(m.size());
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      v[i * m.cols() + c] = m(i, c) / (noise[c] > 0 ? noise[c] : 1.0);
  return v;
}

double r2Of(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double aa = a.squaredNorm(), bb = b.squaredNorm();
  return aa > 0 && bb > 0 ? std::pow(a.dot(b), 2) / (aa * bb) : 0.0;
}

// The change of every row's joint efforts when link j's inertia about its joint axis (the link
// frame's z) grows by 1 kg m^2: the link inertia a joint's armature is classically regrouped with
// (Khalil and Gautier's base parameters), which the fit keeps at the design's value.
Eigen::MatrixXd linkAxisInertiaColumn(const Model& model, const TrajectoryData& data, int j) {
  Model more = model;
  more.inertias[j].I_com_kgm2(2, 2) += 1.0;
  const RigidBodyModel a = makeRigidBodyModel(model), b = makeRigidBodyModel(more);
  DynamicsWorkspace wa(a), wb(b);
  Eigen::VectorXd Qa(model.dof()), Qb(model.dof());
  Eigen::MatrixXd out(data.rows(), model.dof());
  for (int i = 0; i < data.rows(); ++i) {
    const Eigen::VectorXd q = data.q.row(i).transpose(), qd = data.qd.row(i).transpose(),
                          qdd = data.qdd.row(i).transpose();
    inverseDynamics(a, wa, q, qd, qdd, Qa);
    inverseDynamics(b, wb, q, qd, qdd, Qb);
    out.row(i) = (Qb - Qa).transpose();
  }
  return out;
}

// What a referenced one-parameter effect cannot be told apart from with this data (its column
// explains to R^2 > kCollinearR2, in the fit's noise weights): every other one-parameter catalogue
// effect and, for an armature, the inertia of the joint's link about its axis. Such a value is
// the pair's combined value; the report says so beside it.
struct Partners {
  std::vector<std::string> names;  // what the effect cannot be told apart from
  std::string table;               // the names with their R^2
};
Partners partnersOf(const ArmDiagnosis& d, const ArmProblem& P, const Model& model,
                    const TrajectoryData& data, int e, const Eigen::MatrixXd& base) {
  auto column = [&](int f) {
    EffectValue v;
    v.effect = f;
    v.x = Eigen::VectorXd::Ones(1);
    return weighted(P.predict({v}) - base, d.channel_noise);
  };
  const Eigen::VectorXd a = column(e);
  Partners out;
  auto add = [&](const std::string& name, double r2) {
    out.names.push_back(name);
    out.table += (out.table.empty() ? "" : ", ") + name + " (R^2 = " + formatG(r2, 3) + ")";
  };
  for (std::size_t f = 0; f < P.catalogue.size(); ++f) {
    const ArmEffect& g = P.catalogue[f];
    if (static_cast<int>(f) == e || g.params.size() != 1 || g.hasProfile()) continue;
    const double r2 = r2Of(a, column(static_cast<int>(f)));
    if (r2 > defaults::kCollinearR2) add(g.name, r2);
  }
  const int j = model.jointIndex(P.catalogue[e].joint);
  if (P.catalogue[e].effect == "armature" && j >= 0 &&
      j < static_cast<int>(model.inertias.size())) {
    const double r2 = r2Of(a, weighted(linkAxisInertiaColumn(model, data, j), d.channel_noise));
    if (r2 > defaults::kCollinearR2)
      add("the inertia of " + model.joints[j].name +
              "'s link about its axis (kept at the design's value)",
          r2);
  }
  return out;
}

// partnersOf for every referenced effect, in the reference's order.
std::vector<Partners> referencePartners(const ArmDiagnosis& d, const ArmProblem& P,
                                        const Model& model, const TrajectoryData& data,
                                        const IdentificationInput& in) {
  const Eigen::MatrixXd base = P.predict({});
  std::vector<Partners> out;
  for (const auto& ref : in.reference)
    out.push_back(partnersOf(d, P, model, data, P.findEffect(ref.first), base));
  return out;
}

std::string referenceSection(const ArmDiagnosis& d, const ArmProblem& P, const Model& model,
                             const TrajectoryData& data, const IdentificationInput& in,
                             const EffectValues& all, const std::vector<Partners>& partners,
                             std::vector<std::pair<std::string, double>>& M) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < in.reference.size(); ++k) {
    const auto& [name, ref] = in.reference[k];
    const int e = P.findEffect(name);
    const ArmParam& p = P.catalogue[e].params[0];
    const std::string& told = partners[k].table;
    const double fin = firstParam(d.final_fit.values, e), both = firstParam(all, e);
    const Compared cmp = jointSide(P, model, data, all, e);
    std::string ci = "-";
    for (const FittedParameter& f : d.final_fit.params)
      if (f.key == name + "." + p.key)
        ci = formatGOr(f.ci_low, 4, "-") + " .. " + formatGOr(f.ci_high, 4, "-");
    const double diff = ref != 0 ? (cmp.value - ref) / std::abs(ref) : NAN;
    rows.push_back({name, p.unit, std::isfinite(fin) ? formatGOr(fin, 4, "-") : "not added", ci,
                    formatGOr(both, 4, "-"),
                    cmp.how.empty() ? formatGOr(cmp.value, 4, "-")
                                    : formatGOr(cmp.value, 4, "-") + " = " + cmp.how,
                    formatGOr(ref, 4, "-"),
                    std::isfinite(diff) ? report::fixed(100 * diff, 1) + " %" : "-",
                    told.empty() ? "-" : told});
    M.emplace_back("fit/" + name, cmp.value);
    M.emplace_back("indistinguishable/" + name, told.empty() ? 0.0 : 1.0);
    M.emplace_back("reference_difference/" + name, diff);
  }
  std::ostringstream md;
  md << "## Fitted values next to the reference\n\nReference: " << in.reference_source
     << ". \"Final\" is the model the ladder ended with (95 % interval); \"with all referenced\" "
        "refits that model with every referenced effect switched on, so each reference value has "
        "a fitted counterpart. \"Compared\" is that refit on the reference's joint side: a joint's "
        "viscous or armature term is the coefficient of its own speed or acceleration in its own "
        "channel, so a coupled motor that turns the joint adds its term (times the squared ratio "
        "R_kj / R_kk); the difference is of that column. \"Cannot be told apart from\": what the "
        "effect's column cannot be told apart from with these logs (R^2 > "
     << formatG(defaults::kCollinearR2, 3)
     << "); such a value is the combined value of the pair, not the effect's alone.\n\n"
     << report::markdownTable(
            {"effect", "unit", ">final", ">95 % interval", ">with all referenced", ">compared",
             ">reference", ">difference", "cannot be told apart from"},
            rows)
     << "\n";
  return md.str();
}

// Coulomb and viscous coefficients of every joint for the smooth-sign width times each factor.
std::string widthSection(const Model& model, const TrajectoryData& data, const EffectValues& all,
                         const IdentificationInput& in,
                         std::vector<std::pair<std::string, double>>& M) {
  std::vector<std::string> head = {"coefficient"};
  std::vector<std::vector<double>> cols;
  std::vector<std::string> names;
  for (double f : in.width_factors) {
    head.push_back(">w x " + formatGOr(f, 4, "-"));
    TrajectoryData scaled = data;
    scaled.friction_width_fraction *= f;
    const auto P2 = makeTrajectoryProblem(model, scaled);
    const SetFit fit = fitEffects(*P2, all);
    std::vector<double> col;
    names.clear();
    for (const EffectValue& v : fit.values) {
      const std::string& eff = P2->catalogue[v.effect].effect;
      if (eff != "coulomb" && eff != "viscous" && eff != "motor_coulomb" && eff != "motor_viscous")
        continue;
      names.push_back(P2->catalogue[v.effect].name);
      col.push_back(v.x[0]);
      M.emplace_back("width_sweep/" + formatGOr(f, 4, "-") + "/" + names.back(), v.x[0]);
    }
    cols.push_back(col);
  }
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < names.size(); ++k) {
    std::vector<std::string> row = {names[k]};
    for (const auto& c : cols) row.push_back(formatGOr(c[k], 4, "-"));
    rows.push_back(row);
  }
  std::ostringstream md;
  md << "## Friction coefficients over the smooth-sign width\n\nThe Coulomb term is F_c tanh(v / "
        "w) with w = "
     << formatGOr(data.friction_width_fraction, 4, "-")
     << " x the joint's (or motor's) peak speed in the data (the rule of "
     << "docs/calibration.md, fixed before fitting). The model \"with all referenced\" refitted "
        "for w times each "
        "factor (a range of 10):\n\n"
     << report::markdownTable(head, rows) << "\n";
  return md.str();
}

// Residual of every joint over time, before (as designed) and after (final), one axis per joint.
std::string residualSvg(const ArmDiagnosis& d, const ArmProblem& P) {
  report::PlotSpec p;
  p.title = "residual before and after (measured - predicted)";
  p.x_label = "t [s]";
  p.panel_height = 140;
  for (int c = 0; c < P.channels(); ++c) {
    report::PlotPanel panel;
    panel.title = P.channel_names[c];
    panel.y_label = "[" + P.channel_units[c] + "]";
    for (int k = 0; k < 2; ++k) {
      const ArmFit& f = k == 0 ? d.as_designed : d.final_fit;
      report::PlotSeries s;
      s.label = k == 0 ? "before (as designed)"
                       : "after (" + std::to_string(d.added.size()) + " effects added)";
      s.x = P.time;
      for (int i = 0; i < P.rows(); ++i) s.y.push_back(f.residual(i, c));
      panel.series.push_back(s);
    }
    p.panels.push_back(panel);
  }
  return report::plot(p).svg;
}

// Per joint: "joint_4: friction (joint_4.viscous, joint_4.coulomb) named first; held-out error
// 5.74 -> 1.3 N m (4.4x lower); remainder ...". Channels follow the joints' order.
std::vector<std::string> jointAnswers(const ArmDiagnosis& d, const ArmProblem& P,
                                      const Model& model) {
  std::vector<std::string> out;
  const ArmFit &a = d.ladder.front(), &b = d.ladder.back();
  for (int c = 0; c < P.channels() && c < model.dof(); ++c) {
    const std::string& j = model.joints[c].name;
    std::string named;
    for (const std::string& e : d.added)
      if (ofJoint(e, j)) named += (named.empty() ? "" : ", ") + e;
    std::string s = "**" + j + "**: ";
    if (c < static_cast<int>(d.channel_at_floor.size()) && d.channel_at_floor[c])
      s += "not identifiable from these logs (at the logging resolution); ";
    s += named.empty() ? "no effect added" : named + " (in the order added)";
    const bool ok = c < static_cast<int>(a.channel_region_heldout.size()) &&
                    c < static_cast<int>(b.channel_region_heldout.size());
    if (ok) {
      const double x = a.channel_region_heldout[c].rmse, y = b.channel_region_heldout[c].rmse;
      s += "; held-out error " + formatG(x, 3) + " -> " + formatG(y, 3) + " " + P.channel_units[c] +
           (y > 0 ? " (" + formatG(x / y, 3) + "x lower)" : "");
    }
    bool rem = false;
    for (const ArmRemainder& r : d.remainders)
      if (r.channel == P.channel_names[c]) {
        s += "; remainder " + formatG(r.rms, 3) + " " + r.unit + " following " + r.variable + " (" +
             formatG(100 * r.share_final, 3) + " % of what is left)";
        rem = true;
      }
    if (!rem) s += "; no significant remainder";
    out.push_back(s + ".");
  }
  return out;
}

// "fitted / source" of every referenced friction and armature value, one sentence.
std::string referenceAnswer(const ArmProblem& P, const Model& model, const TrajectoryData& data,
                            const IdentificationInput& in, const EffectValues& all,
                            const std::vector<Partners>& partners) {
  std::string s = "fitted / source (" + in.reference_source + "; joint side): ";
  bool first = true;
  for (std::size_t k = 0; k < in.reference.size(); ++k) {
    const auto& [name, ref] = in.reference[k];
    const int e = P.findEffect(name);
    if (e < 0 || P.catalogue[e].effect == "offset") continue;
    const double v = jointSide(P, model, data, all, e).value;
    s += (first ? "" : ", ") + name + " " + formatG(v, 3) + " / " + formatG(ref, 3);
    if (ref != 0 && std::isfinite(v))
      s += " (" + std::string(v >= ref ? "+" : "") + formatG(100 * (v - ref) / std::abs(ref), 2) +
           " %)";
    if (!partners[k].names.empty()) {
      std::string who;
      for (const std::string& w : partners[k].names) who += (who.empty() ? "" : ", ") + w;
      s += " (cannot be told apart from " + who + ": one combined value)";
    }
    first = false;
  }
  return s + ".";
}

}  // namespace

IdentificationReport identificationReport(const ArmDiagnosis& d, const ArmProblem& P,
                                          const Model& model, const TrajectoryData& data,
                                          const IdentificationInput& in) {
  IdentificationReport r;
  const EffectValues all = withReferenced(P, d.final_fit.values, in);
  std::ostringstream md;
  md << "# Identification: " << model.name << " on " << data.file << "\n\nVerdict: " << d.verdict
     << ".\n\n"
     << ladderSection(d, P, r.metrics) << orderSection(d, model, r.metrics);
  const SetFit both = fitEffects(P, all);
  r.answer = jointAnswers(d, P, model);
  if (!in.reference.empty()) {
    const std::vector<Partners> partners = referencePartners(d, P, model, data, in);
    md << referenceSection(d, P, model, data, in, both.values, partners, r.metrics);
    r.answer.push_back(referenceAnswer(P, model, data, in, both.values, partners));
  }
  md << widthSection(model, data, both.values, in, r.metrics)
     << "Residuals before and after on one scale per joint: residuals_before_after.svg.\n";
  r.markdown = md.str();
  r.svg = residualSvg(d, P);
  return r;
}

}  // namespace armstudy::calibration
