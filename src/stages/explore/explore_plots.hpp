#pragma once
// Minimal SVG figures of the [explore] stage, kept in this folder (the plotting module is being
// rewritten; these need nothing from it): a scatter of two objectives and parallel coordinates.
#include <string>
#include <vector>

#include "stages/explore/explore.hpp"

namespace armstudy::explore {

// Objective kx against ky: every feasible candidate grey, infeasible hollow, front red, base blue.
std::string scatterSvg(const std::vector<Candidate>& c, const std::vector<std::size_t>& front,
                       std::size_t base, const ExploreOptions& o, std::size_t kx, std::size_t ky);
// One vertical axis per parameter and objective (each scaled to its range over the candidates);
// one polyline per candidate, front red, base blue, others grey.
std::string parallelSvg(const std::vector<Candidate>& c, const std::vector<std::size_t>& front,
                        std::size_t base, const ExploreOptions& o);

}  // namespace armstudy::explore
