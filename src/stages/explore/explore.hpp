#pragma once
// The [explore] stage (docs/exploration.md): design-space exploration around one design of the
// study. Candidates are variants of that design (io/variant.hpp, so the geometry follows), each
// evaluated by running the study's other stages on it alone; their metrics are the objectives and
// constraints. Exhaustive over a grid for small spaces, else NLopt (global, then a local polish)
// within a budget of evaluations. One candidate evaluation is one work unit ("explore/<name>"),
// and the stages it runs checkpoint their own units, so an interrupted search resumes.
#include <cstdint>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "study/stage.hpp"

namespace armstudy::explore {

struct Parameter {
  std::string key;             // design entry key (io/design_io.hpp setModelEntry)
  std::string label;           // the study's name for it in reports and figures (default: key)
  std::vector<double> values;  // list (or the steps of from..to); SI
  double lo = 0, hi = 0;       // search bounds (min/max of the values)
  double step = 0;             // resolution: candidates are snapped to lo + k*step (0: none)
  int line = 0;
};

// sum_k weight_k * parameter_k within [min, max] (a linear constraint between parameters).
struct LinearConstraint {
  std::vector<std::pair<std::size_t, double>> terms;  // (parameter index, weight)
  double min = -1e300, max = 1e300;
  int line = 0;
};

enum class Goal { None, Maximise, Minimise };

// A metric of the candidate: "<...>/{design}/<...>" of another stage, or the built-in
// "cost/link_length". With a goal it is an objective (Pareto); min/max make it a constraint.
struct Objective {
  std::string label;
  std::string metric;
  std::string unit;  // of the metric, on the figures' axes ("1", "m"); empty: not known
  Goal goal = Goal::None;
  double min = -1e300, max = 1e300;
  double weight = 1;  // in the scalarised NLopt objective (sum of weight * value, sign by goal)
  // What the study can resolve in this metric (its unit): recommended designs that differ by no
  // more are level. 0: one step of a share ("..._fraction": the smallest difference between two
  // candidates' values, one cell or fruit), else only equal values.
  double resolution = 0;
  int line = 0;
};

enum class Method { Grid, Optimise };

struct ExploreOptions {
  Model base;        // the design the candidates derive from
  std::string file;  // the study file (messages)
  int line = 0;
  std::vector<Parameter> parameters;
  std::vector<LinearConstraint> constraints;
  std::vector<Objective> objectives;
  std::vector<std::string> stages;  // stages run on each candidate (registry names)
  Method method = Method::Grid;
  std::string algorithm = "DIRECT_L";  // NLopt global: DIRECT_L, CRS2, ISRES
  std::string polish = "BOBYQA";       // NLopt local: BOBYQA, COBYLA, NELDERMEAD, none
  int budget = 60;                     // evaluations (global + polish)
  double polish_share = 0.25;          // of the budget
  std::uint64_t seed = 1;
  int front_designs = 3;  // front designs written with their stage outputs
  std::string validate() const;
};

ExploreOptions readExploreOptions(io::TableReader& r, const SectionInput& in);

// One evaluated candidate.
struct Candidate {
  std::string name;
  std::vector<std::pair<std::string, double>> overrides;  // empty for the base design
  std::vector<double> params;                             // parameter values (SI), parameter order
  std::vector<double> values;        // objective metric values, objective order
  bool feasible = true;              // every constraint met
  std::vector<std::string> adapted;  // geometry-that-follows notes
};

// Indices of the non-dominated feasible candidates (objectives with a goal), ascending.
// a dominates b when a is no worse in every goal and better in one; equal vectors both stay.
std::vector<std::size_t> paretoFront(const std::vector<Candidate>& cands,
                                     const std::vector<Objective>& objectives);

StageResult runExploreStage(const StageContext& ctx, const ExploreOptions& o);

// Built-in cost proxy: sum of |(x, y, z)| of every table row after the first (the first places
// the arm on its base) plus |TCP offset| [m].
double totalLinkLength(const Model& m);

// A candidate name usable as a design name and file name: "+" -> "__", "=" -> "_"
// ("final_prototype_7dof+j4.x=0.4" -> "final_prototype_7dof__j4.x_0.4").
std::string fileSafeName(const std::string& candidate);

}  // namespace armstudy::explore
