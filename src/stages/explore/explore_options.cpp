#include <cmath>

#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/toml_reader.hpp"
#include "io/variant.hpp"
#include "stages/explore/explore.hpp"

namespace armstudy::explore {

using io::TableReader;

namespace {

// Grid of the exhaustive search above this many candidates needs method = "optimise".
constexpr long kMaxGridCandidates = 5000;

Parameter readParameter(TableReader& r, const Model& base) {
  Parameter p;
  p.line = r.line();
  p.key = r.string("key");
  p.label = r.string("label", p.key);
  Dimension dim;
  std::string err;
  if (!modelEntryDimension(base, p.key, dim, err)) r.fail("key", err);
  checkVariantName(base.name, {{p.key, 0.0}}, r.file(), p.line);  // candidates' names name files
  if (r.has("values")) {
    if (r.has("from") || r.has("to")) r.fail("values", "give either values or from/to, not both");
    const toml::array* a = r.array("values");
    if (!a || a->empty()) r.fail("values", "needs a non-empty array of values");
    for (const auto& e : *a)
      p.values.push_back(io::nodeQuantity(e, dim, r.file(), r.keyPath("values")));
    p.lo = p.hi = p.values[0];
    for (double v : p.values) p.lo = std::min(p.lo, v), p.hi = std::max(p.hi, v);
  } else {
    p.lo = r.quantity("from", dim);
    p.hi = r.quantity("to", dim);
    if (!(p.hi > p.lo)) r.fail("to", "`to` must be greater than `from`");
    p.step = r.quantity("step", dim, 0.0);
    if (p.step < 0) r.fail("step", "step must be positive");
    if (p.step > 0) {
      const long n = std::lround(std::floor((p.hi - p.lo) / p.step + 1e-9));
      if (n > 10000) r.fail("step", "more than 10000 steps");
      for (long k = 0; k <= n; ++k) p.values.push_back(p.lo + k * p.step);
    }
  }
  r.finish();
  return p;
}

// The unit of the metrics whose unit their name tells: shares and ratios [1], the built-in link
// length [m], drive currents [A]; "" for the others (the study file gives it as `unit`).
std::string defaultUnit(const std::string& metric) {
  auto ends = [&](const std::string& tail) {
    return metric.size() >= tail.size() &&
           metric.compare(metric.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (metric == "cost/link_length") return "m";
  if (ends("_fraction") || ends("_ratio")) return "1";
  if (ends("_A")) return "A";
  return "";
}

// One [[explore.constraint]]: a linear combination of parameters between min and max.
LinearConstraint readConstraint(TableReader& cr, const ExploreOptions& o) {
  LinearConstraint c;
  c.line = cr.line();
  const toml::table* terms = cr.table("terms");
  if (!terms || terms->empty())
    cr.fail("terms", "needs terms = { \"<parameter key>\" = weight, ... }");
  for (auto&& [key, v] : *terms) {
    std::size_t idx = o.parameters.size();
    for (std::size_t i = 0; i < o.parameters.size(); ++i)
      if (o.parameters[i].key == key.str()) idx = i;
    if (idx == o.parameters.size())
      cr.fail("terms", "'" + std::string(key.str()) + "' is not a parameter");
    const auto w = v.value<double>();
    if (!w || !std::isfinite(*w)) cr.fail("terms", "weights are plain numbers");
    c.terms.emplace_back(idx, *w);
  }
  // Bounds carry the unit of the first parameter term (constraints between lengths or angles).
  Dimension dim;
  std::string err;
  modelEntryDimension(o.base, o.parameters[c.terms[0].first].key, dim, err);
  if (!cr.has("min") && !cr.has("max")) cr.fail("terms", "a constraint needs min or max");
  c.min = cr.quantity("min", dim, -1e300);
  c.max = cr.quantity("max", dim, 1e300);
  cr.finish();
  return c;
}

// One [[explore.objective]]: a metric with a goal, or bounds that make it a constraint.
Objective readObjective(TableReader& orr) {
  Objective ob;
  ob.line = orr.line();
  ob.metric = orr.string("metric");
  if (ob.metric != "cost/link_length" && ob.metric.find("{design}") == std::string::npos)
    orr.fail("metric",
             "a stage metric names the candidate as {design}, e.g. "
             "\"reach/row/{design}/reachable_fraction\" (or use \"cost/link_length\")");
  ob.label = orr.string("label", ob.metric);
  ob.unit = orr.string("unit", defaultUnit(ob.metric));
  const std::string goal = orr.string("goal", "");
  if (goal == "max")
    ob.goal = Goal::Maximise;
  else if (goal == "min")
    ob.goal = Goal::Minimise;
  else if (!goal.empty())
    orr.fail("goal", "goal is \"max\" or \"min\"");
  ob.min = orr.number("min", -1e300);
  ob.max = orr.number("max", 1e300);
  ob.weight = orr.number("weight", 1.0);
  ob.resolution = orr.number("resolution", 0.0);
  if (!(ob.resolution >= 0)) orr.fail("resolution", "resolution must be 0 or more");
  if (ob.goal == Goal::None && !orr.has("min") && !orr.has("max"))
    orr.fail("metric", "an objective needs a goal, or min/max to be a constraint");
  orr.finish();
  return ob;
}

}  // namespace

std::string ExploreOptions::validate() const {
  if (parameters.empty()) return "no parameters";
  if (budget < 1) return "budget must be at least 1";
  if (!(polish_share >= 0 && polish_share < 1)) return "polish_share must be in [0, 1)";
  bool goal = false;
  for (const auto& o : objectives) goal |= o.goal != Goal::None;
  if (!goal) return "no objective with a goal";
  return "";
}

ExploreOptions readExploreOptions(TableReader& r, const SectionInput& in) {
  ExploreOptions o;
  o.file = in.top.file();
  o.line = r.line();
  const std::string design = r.string("design");
  const Model* base = nullptr;
  for (const Model* m : in.designs)
    if (m->name == design) base = m;
  if (!base) r.fail("design", "design '" + design + "' is not part of the study");
  o.base = *base;

  const toml::array* ps = r.array("parameter");
  if (!ps || ps->empty()) r.fail("parameter", "needs at least one [[explore.parameter]]");
  r.forEachTable("parameter", [&](TableReader& pr) {
    Parameter p = readParameter(pr, o.base);
    for (const auto& q : o.parameters)
      if (q.key == p.key) pr.fail("key", "parameter '" + p.key + "' is given twice");
    o.parameters.push_back(std::move(p));
  });
  r.forEachTable("constraint",
                 [&](TableReader& cr) { o.constraints.push_back(readConstraint(cr, o)); });
  const toml::array* os = r.array("objective");
  if (!os || os->empty()) r.fail("objective", "needs at least one [[explore.objective]]");
  r.forEachTable("objective",
                 [&](TableReader& orr) { o.objectives.push_back(readObjective(orr)); });
  if (r.has("stages")) {
    o.stages = r.stringArray("stages");
  } else {
    for (const char* s : {"reach", "dexterity", "harvest"})
      if (in.top.table(s)) o.stages.push_back(s);
  }
  for (const auto& s : o.stages) {
    if (s == "explore") r.fail("stages", "explore cannot run itself on its candidates");
    if (!in.top.table(s) && !in.top.array(s))
      r.fail("stages", "the study has no [" + s + "] section");
  }
  long grid = 1;
  bool all_listed = true;
  for (const auto& p : o.parameters) {
    all_listed &= !p.values.empty();
    grid = p.values.empty()
               ? grid
               : std::min(grid * static_cast<long>(p.values.size()), kMaxGridCandidates + 1);
  }
  const std::string method =
      r.string("method", all_listed && grid <= kMaxGridCandidates ? "grid" : "optimise");
  if (method == "grid") {
    if (!all_listed)
      r.fail("method", "an exhaustive grid needs values or a step for every parameter");
    if (grid > kMaxGridCandidates)
      r.fail("method", "the grid has more than " + std::to_string(kMaxGridCandidates) +
                           " candidates; use method = \"optimise\"");
    o.method = Method::Grid;
  } else if (method == "optimise") {
    o.method = Method::Optimise;
  } else {
    r.fail("method", "method is \"grid\" or \"optimise\"");
  }
  o.algorithm = r.string("algorithm", o.algorithm);
  if (o.algorithm != "DIRECT_L" && o.algorithm != "CRS2" && o.algorithm != "ISRES")
    r.fail("algorithm", "algorithm is DIRECT_L, CRS2 or ISRES");
  o.polish = r.string("polish", o.polish);
  if (o.polish != "BOBYQA" && o.polish != "COBYLA" && o.polish != "NELDERMEAD" &&
      o.polish != "none")
    r.fail("polish", "polish is BOBYQA, COBYLA, NELDERMEAD or none");
  o.budget = r.integerIn("budget", o.budget, 1, 100000);
  o.polish_share = r.number("polish_share", o.polish_share);
  o.seed = r.seed("seed", o.seed);
  o.front_designs = r.integerIn("front_designs", o.front_designs, 0, 1000);
  const std::string err = o.validate();
  if (!err.empty()) r.fail("objective", err);
  r.finish();
  return o;
}

}  // namespace armstudy::explore
