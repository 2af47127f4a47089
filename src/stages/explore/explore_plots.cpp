#include "stages/explore/explore_plots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/design_io.hpp"

namespace armstudy::explore {

using report::Better;

namespace {

const report::Rgb kFrontColour{214, 39, 40}, kBaseColour{31, 119, 180}, kOtherColour{150, 150, 150};

Better better(Goal g) {
  return g == Goal::Maximise ? Better::higher : g == Goal::Minimise ? Better::lower : Better::none;
}

bool onFront(const std::vector<std::size_t>& front, std::size_t i) {
  return std::find(front.begin(), front.end(), i) != front.end();
}

// A candidate's values on the parallel axes: its parameters (the base design's from the base
// model), then its objectives.
std::vector<double> parallelRow(const ExploreOptions& o, const Candidate& k) {
  std::vector<double> row;
  for (std::size_t p = 0; p < o.parameters.size(); ++p) {
    double v = std::numeric_limits<double>::quiet_NaN();
    std::string error;
    if (p < k.params.size())
      v = k.params[p];
    else if (!modelEntryValue(o.base, o.parameters[p].key, v, error))
      v = std::numeric_limits<double>::quiet_NaN();
    row.push_back(v);
  }
  row.insert(row.end(), k.values.begin(), k.values.end());
  return row;
}

}  // namespace

std::string parameterAxisLabel(const ExploreOptions& o, const Parameter& p) {
  Dimension d = Dimension::Dimensionless;
  std::string error;
  const std::string& name = p.label.empty() ? p.key : p.label;  // the key when no label is given
  if (!modelEntryDimension(o.base, p.key, d, error)) return name;
  return name + " [" + siUnit(d) + "]";
}

std::string objectiveAxisLabel(const Objective& ob) {
  if (ob.unit.empty() || ob.label.find('[') != std::string::npos) return ob.label;
  return ob.label + " [" + ob.unit + "]";
}

report::Drawing frontScatterFigure(const std::vector<Candidate>& c,
                                   const std::vector<std::size_t>& front, std::size_t base,
                                   const ExploreOptions& o, std::size_t kx, std::size_t ky) {
  report::PlotSeries other, infeasible, on_front, base_design;
  other.label = "other designs";
  infeasible.label = "designs breaking a constraint";
  on_front.label = "Pareto front";
  base_design.label = "base design";
  for (report::PlotSeries* s : {&other, &infeasible, &on_front, &base_design})
    s->lines = false, s->markers = true;
  other.colour = infeasible.colour = kOtherColour;
  infeasible.marker = report::Marker::ring;
  on_front.colour = kFrontColour;
  on_front.marker_size = 3.6;
  base_design.colour = kBaseColour;
  base_design.marker = report::Marker::square;
  base_design.marker_size = 5;
  for (std::size_t i = 0; i < c.size(); ++i) {
    report::PlotSeries& s = i == base           ? base_design
                            : onFront(front, i) ? on_front
                            : c[i].feasible     ? other
                                                : infeasible;
    s.x.push_back(c[i].values[kx]);
    s.y.push_back(c[i].values[ky]);
  }
  report::PlotSpec spec;
  const Objective &ox = o.objectives[kx], &oy = o.objectives[ky];
  spec.title = "Pareto front: " + ox.label + " and " + oy.label;
  spec.x_label = report::withBetter(objectiveAxisLabel(ox), better(ox.goal));
  report::PlotPanel panel;
  panel.y_label = report::withBetter(objectiveAxisLabel(oy), better(oy.goal));
  for (report::PlotSeries* s : {&other, &infeasible, &on_front, &base_design})
    if (!s->x.empty()) panel.series.push_back(*s);
  spec.panels = {panel};
  spec.width = 640;
  spec.x_margin = 0.06;  // as the y axis: no marker on the frame
  return report::plot(spec);
}

report::Drawing parallelFigure(const std::vector<Candidate>& c,
                               const std::vector<std::size_t>& front, std::size_t base,
                               const ExploreOptions& o) {
  report::ParallelSpec spec;
  spec.title =
      "Parameters and objectives of every candidate (each objective turned so that "
      "better is up)";
  for (const Parameter& p : o.parameters) spec.axes.push_back({parameterAxisLabel(o, p)});
  for (const Objective& ob : o.objectives)
    spec.axes.push_back({objectiveAxisLabel(ob), better(ob.goal)});
  report::ParallelGroup other{"other designs", kOtherColour, 0.8, {}},
      on_front{"Pareto front", kFrontColour, 1.6, {}},
      base_design{"base design", kBaseColour, 2.4, {}};
  for (std::size_t i = 0; i < c.size(); ++i)
    (i == base           ? base_design
     : onFront(front, i) ? on_front
                         : other)
        .items.push_back(parallelRow(o, c[i]));
  for (report::ParallelGroup* g : {&other, &on_front, &base_design})
    if (!g->items.empty()) spec.groups.push_back(*g);
  return report::parallelCoordinates(spec);
}

}  // namespace armstudy::explore
