#pragma once
// The reach stage's answer (private to stages/reach): which design reaches most and is more
// dexterous, from the stage's summary and the grid's maps.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "report/document.hpp"
#include "stages/reach/reach_report.hpp"

namespace armstudy::reach_report {

// The stage's answer and warnings (StageResult::answer/warnings) from its summary: per grid and
// pose list, which design reaches most and by how much, and the dexterity verdicts where both
// reach; a design that reaches nothing is a warning.
void reachAnswer(const nlohmann::ordered_json& summary, std::vector<std::string>& answer,
                 std::vector<std::string>& warnings);

// Dexterity of design pairs on the poses both reach: mean manipulability and its translational and
// rotational parts of each, and a verdict that ranks the pair only when the combined value and
// both parts agree. Appends a table and a list of verdicts to doc; returns the summary.json block.
// The designs' parts are computed on `threads` threads each.
nlohmann::ordered_json dexterityComparison(
    const std::vector<const Model*>& models, const TaskGrid& g,
    const std::vector<PoseSweep>& sweeps,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs, int threads,
    report::Document& doc);

}  // namespace armstudy::reach_report
