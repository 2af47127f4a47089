#pragma once
// The figures of the [explore] stage, laid out by the plotting module (report/plot.hpp): a scatter
// of two objectives and parallel coordinates of parameters and objectives.
#include <string>
#include <vector>

#include "report/plot.hpp"
#include "stages/explore/explore.hpp"

namespace armstudy::explore {

// A parameter's axis label: the study's name for it with its SI unit ("upper arm [m]").
std::string parameterAxisLabel(const ExploreOptions& o, const Parameter& p);
// An objective's axis label: its label with its unit (unless the label already has one).
std::string objectiveAxisLabel(const Objective& ob);

// Objective kx against ky, each axis saying which way is better: the front red, the other feasible
// candidates grey, infeasible ones hollow grey, the base design a blue square.
report::Drawing frontScatterFigure(const std::vector<Candidate>& c,
                                   const std::vector<std::size_t>& front, std::size_t base,
                                   const ExploreOptions& o, std::size_t kx, std::size_t ky);
// One vertical axis per parameter (with its SI unit) and objective (turned so that better is up);
// one polyline per candidate: the front red, the base design blue, the others grey.
report::Drawing parallelFigure(const std::vector<Candidate>& c,
                               const std::vector<std::size_t>& front, std::size_t base,
                               const ExploreOptions& o);

}  // namespace armstudy::explore
