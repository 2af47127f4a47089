// Candidate evaluation and the two searches of the [explore] stage (explore.hpp).
#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <map>
#include <nlopt.hpp>

#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/variant.hpp"
#include "stages/explore/explore_internal.hpp"

namespace armstudy::explore {

namespace fs = std::filesystem;

namespace {
constexpr const char* kUnitMagic = "armstudy-explore-unit-v1";
// NLopt penalties: a candidate breaking a parameter constraint is not evaluated and scores
// kInfeasible plus kPenalty times the violation; a metric constraint adds kPenalty x violation.
constexpr double kInfeasible = 1e6;
constexpr double kPenalty = 1e3;
// Smallest initial step of the local polish, as a fraction of each parameter's range.
constexpr double kPolishInitialStep = 0.05;
// The budget counts candidates the stages evaluate; NLopt's own calls also include revisits of
// snapped points and points breaking a parameter constraint, which cost nothing. This caps the
// calls per unit of budget, so that a search circling among known points still ends (assumption:
// 25 calls per evaluation; DIRECT_L needed 2.9 on the shipped study).
constexpr int kMaxCallsPerEvaluation = 25;
}  // namespace

double totalLinkLength(const Model& m) {
  double L = std::sqrt(m.tcp.x * m.tcp.x + m.tcp.y * m.tcp.y + m.tcp.z * m.tcp.z);
  for (int i = 1; i < m.dof(); ++i) {
    const PoseXYZABG& p = m.joints[i].offset;
    L += std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
  }
  return L;
}

std::vector<std::size_t> paretoFront(const std::vector<Candidate>& c,
                                     const std::vector<Objective>& obj) {
  // Value in "larger is better" form.
  auto better = [&](std::size_t k, double v) { return obj[k].goal == Goal::Maximise ? v : -v; };
  auto dominates = [&](const Candidate& a, const Candidate& b) {
    bool strict = false;
    for (std::size_t k = 0; k < obj.size(); ++k) {
      if (obj[k].goal == Goal::None) continue;
      const double va = better(k, a.values[k]), vb = better(k, b.values[k]);
      if (va < vb) return false;
      strict |= va > vb;
    }
    return strict;
  };
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c[i].feasible) continue;
    bool dominated = false;
    for (std::size_t j = 0; j < c.size() && !dominated; ++j)
      dominated = j != i && c[j].feasible && dominates(c[j], c[i]);
    if (!dominated) front.push_back(i);
  }
  return front;
}

Evaluator::Evaluator(const StageContext& ctx, const ExploreOptions& o) : ctx_(ctx), o_(o) {
  inner_options_ = ctx.options;
  inner_options_.progress = false;
  inner_options_.preview_stride = 0;  // a candidate's maps are not what a person waits for
  scratch_ = (fs::path(ctx.output_dir) / "explore" / ".scratch").string();
  for (const std::string& name : o.stages)
    for (const StudySection& s : ctx.study.sections)
      if (s.stage && s.settings && name == stageName(s)) sections_.push_back(s);
}

std::string Evaluator::stageName(const StudySection& s) { return s.stage->name(); }

Study Evaluator::candidateStudy(const Model& m, const Overrides& ov) const {
  // The study with the candidate as its one design and the explored stages as its sections.
  Study sub = ctx_.study;
  sub.designs = {StudyDesign{m, o_.base.name, ov, 0.0}};
  sub.sections = sections_;
  return sub;
}

StageResult Evaluator::runStages(const Model& m, const Overrides& ov, const std::string& dir,
                                 const std::map<std::string, double>& scale_tops) const {
  const Study sub = candidateStudy(m, ov);
  RunOptions options = inner_options_;
  options.shared_scale_tops = scale_tops;
  StageResult all;
  for (const StudySection& s : sections_) {
    // A candidate is one unit, computed by one process: its stages run their units here.
    const StageContext sc{sub, options, dir, ctx_.units.local(), ctx_.threads, {}, {}};
    StageResult r = s.stage->run(sc, *s.settings);
    all.metrics.merge(r.metrics);
    for (const auto& [scale, top] : r.scale_tops)
      all.scale_tops[scale] = std::max(all.scale_tops[scale], top);
    all.files.insert(all.files.end(), r.files.begin(), r.files.end());
    all.reports.insert(all.reports.end(), r.reports.begin(), r.reports.end());
    all.units_resumed += r.units_resumed;
  }
  return all;
}

std::vector<double> Evaluator::metricValues(const Model& m, const StudyMetrics& metrics) const {
  std::vector<double> v;
  for (const Objective& ob : o_.objectives) {
    if (ob.metric == "cost/link_length") {
      v.push_back(totalLinkLength(m));
      continue;
    }
    std::string name = ob.metric;
    name.replace(name.find("{design}"), 8, m.name);
    auto it = metrics.scalars.find(name);
    if (it == metrics.scalars.end()) {
      std::string have;
      int n = 0;
      for (const auto& [k, x] : metrics.scalars)
        if (n++ < 12) have += (have.empty() ? "" : ", ") + k;
      throw InputError(o_.file, ob.line, "explore.objective.metric",
                       "the stages " +
                           std::string(sections_.empty() ? "(none)" : "run on the candidate") +
                           " give no metric '" + name + "' (they give: " + have + ")");
    }
    v.push_back(it->second);
  }
  return v;
}

bool Evaluator::parametersFeasible(const std::vector<double>& params, double& violation) const {
  violation = 0;
  for (const LinearConstraint& c : o_.constraints) {
    double s = 0;
    for (const auto& [i, w] : c.terms) s += w * params[i];
    violation += std::max(0.0, c.min - s) + std::max(0.0, s - c.max);
  }
  return violation == 0;
}

double Evaluator::metricViolation(const std::vector<double>& values) const {
  double v = 0;
  for (std::size_t k = 0; k < o_.objectives.size(); ++k) {
    const Objective& ob = o_.objectives[k];
    v += std::max(0.0, ob.min - values[k]) + std::max(0.0, values[k] - ob.max);
  }
  return v;
}

std::vector<double> Evaluator::baseParams() const {
  std::vector<double> p;
  for (const Parameter& P : o_.parameters) {
    double v = 0;
    std::string err;
    ARMSTUDY_CHECK(modelEntryValue(o_.base, P.key, v, err), err);  // keys were checked on reading
    p.push_back(v);
  }
  return p;
}

Overrides Evaluator::overridesOf(const std::vector<double>& params) const {
  Overrides ov;
  for (std::size_t i = 0; i < params.size(); ++i) ov.emplace_back(o_.parameters[i].key, params[i]);
  return ov;
}

std::vector<std::size_t> Evaluator::evaluate(const std::vector<std::vector<double>>& batch_params,
                                             bool base) {
  // New candidates only; known ones (a search revisiting a point) are returned as they are.
  std::vector<std::size_t> out(batch_params.size());
  std::vector<std::size_t> fresh;
  std::vector<Model> models;
  for (std::size_t b = 0; b < batch_params.size(); ++b) {
    const Overrides ov = base ? Overrides{} : overridesOf(batch_params[b]);
    const std::string name = base ? o_.base.name : variantName(o_.base.name, ov);
    auto it = by_name_.find(name);
    if (it != by_name_.end()) {
      out[b] = it->second;
      continue;
    }
    Candidate c;
    c.name = name;
    c.overrides = ov;
    c.params = base ? baseParams() : batch_params[b];
    Model m = base ? o_.base : deriveVariant(o_.base, ov, o_.file, o_.line);
    for (std::size_t a = o_.base.assumptions.size(); a < m.assumptions.size(); ++a)
      c.adapted.push_back(m.assumptions[a]);
    by_name_[name] = cands_.size();
    out[b] = cands_.size();
    fresh.push_back(cands_.size());
    cands_.push_back(std::move(c));
    models.push_back(std::move(m));
  }
  if (fresh.empty()) return out;
  UnitBatch batch;
  for (std::size_t f : fresh) batch.ids.push_back("explore/" + cands_[f].name);
  batch.load = [&](std::size_t k, const std::string& bytes) {
    UnitReader r(bytes, kUnitMagic);
    std::vector<double> v;
    r.getVector(v);
    if (!r.finished() || v.size() != o_.objectives.size()) return false;
    cands_[fresh[k]].values = std::move(v);
    return true;
  };
  batch.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
    // Candidates one after another; each stage spreads its own work over the run's threads.
    for (std::size_t k : todo) {
      const StageResult r = runStages(models[k], cands_[fresh[k]].overrides, scratch_);
      std::error_code ec;
      fs::remove_all(scratch_, ec);
      inner_resumed_ += r.units_resumed;
      cands_[fresh[k]].values = metricValues(models[k], r.metrics);
      UnitWriter w(kUnitMagic);
      w.putVector(cands_[fresh[k]].values);
      done(k, w.bytes());
    }
  };
  units_resumed_ += ctx_.units.run(batch);
  for (std::size_t f : fresh) cands_[f].feasible = metricViolation(cands_[f].values) == 0;
  return out;
}

// ---- searches ----------------------------------------------------------------------------------

void Evaluator::searchGrid() {
  std::vector<std::vector<double>> pts;
  std::vector<std::size_t> counter(o_.parameters.size(), 0);
  for (bool done = false; !done;) {
    std::vector<double> p;
    for (std::size_t i = 0; i < counter.size(); ++i)
      p.push_back(o_.parameters[i].values[counter[i]]);
    double viol;
    if (parametersFeasible(p, viol))
      pts.push_back(p);
    else
      ++skipped_;
    int k = static_cast<int>(counter.size()) - 1;  // the last parameter varies fastest
    for (; k >= 0; --k) {
      if (++counter[k] < o_.parameters[k].values.size()) break;
      counter[k] = 0;
    }
    done = k < 0;
  }
  evaluate(pts, false);
  status_ = "exhaustive grid: " + std::to_string(pts.size()) + " candidate(s), " +
            std::to_string(skipped_) + " left out by the parameter constraints";
}

std::vector<double> Evaluator::snap(const std::vector<double>& x01) const {
  std::vector<double> p(x01.size());
  for (std::size_t i = 0; i < x01.size(); ++i) {
    const Parameter& P = o_.parameters[i];
    double v = P.lo + std::clamp(x01[i], 0.0, 1.0) * (P.hi - P.lo);
    if (P.step > 0) {
      v = P.lo + std::round((v - P.lo) / P.step) * P.step;
      v = std::min(v, P.hi);
    } else if (!P.values.empty()) {  // a list: the nearest listed value
      double best = P.values[0];
      for (double c : P.values)
        if (std::abs(c - v) < std::abs(best - v)) best = c;
      v = best;
    }
    p[i] = v;
  }
  return p;
}

double Evaluator::score(const std::vector<double>& x01) {
  const std::vector<double> p = snap(x01);
  double viol;
  if (!parametersFeasible(p, viol)) {
    ++skipped_;
    return kInfeasible + kPenalty * viol;
  }
  const Candidate& c = cands_[evaluate({p}, false)[0]];
  double f = kPenalty * metricViolation(c.values);
  for (std::size_t k = 0; k < o_.objectives.size(); ++k) {
    const Objective& ob = o_.objectives[k];
    if (ob.goal == Goal::Maximise) f -= ob.weight * c.values[k];
    if (ob.goal == Goal::Minimise) f += ob.weight * c.values[k];
  }
  return f;
}

void Evaluator::searchOptimise() {
  const unsigned n = static_cast<unsigned>(o_.parameters.size());
  const int polish_budget =
      o_.polish == "none" ? 0 : static_cast<int>(std::floor(o_.budget * o_.polish_share));
  const int global_budget = std::max(1, o_.budget - polish_budget);
  nlopt::srand(o_.seed);
  std::exception_ptr error;
  struct Data {
    Evaluator* self;
    std::exception_ptr* error;
    nlopt::opt* opt;
    std::size_t stop_at;  // candidates known when this phase's budget is spent
    int calls = 0;
    bool budget_spent = false;
  };
  auto fn = [](unsigned, const double* x, double*, void* data) -> double {
    auto* d = static_cast<Data*>(data);
    try {
      ++d->calls;
      const double f = d->self->score(std::vector<double>(x, x + d->self->o_.parameters.size()));
      if (d->self->cands_.size() >= d->stop_at) {  // the budget of evaluations is spent
        d->budget_spent = true;
        d->opt->force_stop();
      }
      return f;
    } catch (...) {
      *d->error = std::current_exception();
      d->opt->force_stop();
      return 0;
    }
  };
  // Start at the base design (clamped into the box; DIRECT ignores it, CRS2 and ISRES add it to
  // their population).
  std::vector<double> x(n);
  const std::vector<double> p0 = baseParams();
  for (unsigned i = 0; i < n; ++i) {
    const Parameter& P = o_.parameters[i];
    x[i] = std::clamp((p0[i] - P.lo) / (P.hi - P.lo), 0.0, 1.0);
  }
  const nlopt::algorithm global = o_.algorithm == "CRS2"    ? nlopt::GN_CRS2_LM
                                  : o_.algorithm == "ISRES" ? nlopt::GN_ISRES
                                                            : nlopt::GN_DIRECT_L;
  // One phase: NLopt until `budget` new candidates are evaluated (or the algorithm ends, or the
  // cap on its calls); "<n> evaluations in <calls> calls, <how it ended>".
  auto run = [&](nlopt::algorithm a, int budget, double initial_step) {
    nlopt::opt opt(a, n);
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_maxeval(kMaxCallsPerEvaluation * budget);
    if (initial_step > 0) opt.set_initial_step(initial_step);
    const std::size_t known = cands_.size();
    Data d{this, &error, &opt, known + static_cast<std::size_t>(budget)};
    opt.set_min_objective(fn, &d);
    double f = 0;
    std::string how;
    try {
      const nlopt::result r = opt.optimize(x, f);
      how = r == nlopt::MAXEVAL_REACHED ? "call cap reached"
                                        : "NLopt status " + std::to_string(static_cast<int>(r));
    } catch (const std::exception& e) {
      how = e.what();
    }
    if (error) std::rethrow_exception(error);
    if (d.budget_spent) how = "budget spent";
    return std::to_string(cands_.size() - known) + " evaluations in " + std::to_string(d.calls) +
           " calls, " + how;
  };
  const std::string gs = run(global, global_budget, 0);
  status_ = "NLopt " + o_.algorithm + " (" + gs + ")";
  if (polish_budget > 0) {
    // Polish from the best feasible candidate so far (by the scalarised objective).
    double best = 1e300;
    for (const Candidate& c : cands_) {
      if (!c.feasible || c.overrides.empty()) continue;
      double f = 0;
      for (std::size_t k = 0; k < o_.objectives.size(); ++k) {
        const Objective& ob = o_.objectives[k];
        if (ob.goal == Goal::Maximise) f -= ob.weight * c.values[k];
        if (ob.goal == Goal::Minimise) f += ob.weight * c.values[k];
      }
      if (f < best) {
        best = f;
        for (unsigned i = 0; i < n; ++i) {
          const Parameter& P = o_.parameters[i];
          x[i] = (c.params[i] - P.lo) / (P.hi - P.lo);
        }
      }
    }
    double step = kPolishInitialStep;
    for (const Parameter& P : o_.parameters)
      if (P.step > 0) step = std::max(step, P.step / (P.hi - P.lo));
    const nlopt::algorithm local = o_.polish == "COBYLA"       ? nlopt::LN_COBYLA
                                   : o_.polish == "NELDERMEAD" ? nlopt::LN_NELDERMEAD
                                                               : nlopt::LN_BOBYQA;
    const std::string ls = run(local, polish_budget, step);
    status_ += ", then " + o_.polish + " (" + ls + ")";
  }
}

}  // namespace armstudy::explore
