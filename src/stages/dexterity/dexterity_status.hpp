#pragma once
// Why each stem cell is (not) approachable (docs/dexterity.md, "Collisions"): the cells' statuses
// counted per half circle, the colliding pairs, the status map figure, and their report and
// summary.json entries.
#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "dexterity/dexterity_audit.hpp"
#include "dexterity/dexterity_map.hpp"
#include "report/document.hpp"
#include "stages/dexterity/dexterity_output.hpp"
#include "study/writer.hpp"

namespace armstudy::dexterity {

// The halves of the circle a count covers: gamma < 0 / gamma >= 0 (left and right of the approach
// from the robot), and the near / far half, |gamma| < 90 deg (the robot's side of the row) /
// |gamma| > 90 deg (the cells at exactly +-90 deg, beside the stem along the row, are in neither).
enum class Half { Negative = 0, NonNegative = 1, Near = 2, Far = 3 };
inline constexpr int kHalves = 4;
bool inHalf(double gamma_rad, Half h);

// A report number with `prec` decimals; "-" for NaN (nothing to report).

// Cells per status (ReachStatus) in each half.
struct StatusCounts {
  std::array<std::array<int, kReachStatusCount>, kHalves> by{};
  std::array<int, kHalves> cells{};
  int count(Half h, ReachStatus s) const { return by[static_cast<int>(h)][static_cast<int>(s)]; }
  int total(Half h) const { return cells[static_cast<int>(h)]; }
};
StatusCounts statusCounts(const DexterityMap& map);

// The most frequent colliding pair of the cells with `status` in half `h` (all cells when h is
// null), "" when none.
std::string mostFrequentPair(const DexterityMap& map, ReachStatus status, const Half* h = nullptr);

// What limits a half: the most frequent status other than reachable there, named as an effect
// ("neighbouring stems (j9-obstacle:stem_+1)", "self-collision (j3-j7)", "joint limits",
// "reach"); "nothing" when every cell is reachable.
std::string limitingEffect(const DexterityMap& map, const StatusCounts& c, Half h);

// Writes <design>_status.svg/.png (one colour per status) under `sub` and returns the report's
// table cell showing it; a map whose cells all have one status would be one colour, so it is not
// drawn and the cell says it in words ("100 % of the 49 cells reachable").
std::string writeStatusMap(const DexterityMap& map, const std::string& sub, Writer& out);

// The report's status section: the status table per half circle and the colliding pairs.
report::Document statusSection(const DexterityMap& map, const StatusCounts& c);

// d["status"]: counts per half and status name, the checked pairs, the most frequent pairs.
void addStatusJson(const DexterityMap& map, const StatusCounts& c, nlohmann::ordered_json& d);

// The row sweep (DexterityOptions::row_sweep, dexterity_row.cpp): the design's map again for each
// spacing; per map the approachable cells of the near and far half and what limits each, with
// `main` (the map with options.collision) first. Sets d["row_sweep"] and `halves` (one per map,
// in the same order) and returns the report section; empty when the study has no row and the grid
// no far half.
report::Document rowSweep(const Model& m, const DexterityOptions& options, const DexterityMap& main,
                          int threads, nlohmann::ordered_json& d, std::vector<RowHalves>& halves);

// The study-wide fields of summary.json (grid and settings) with an empty design list, and the
// report's title and opening paragraphs (dexterity_intro.cpp).
nlohmann::ordered_json settingsJson(const DexterityOptions& options);
report::Document reportIntro(const DexterityOptions& options);

// The files of an audit (auditDexterityMap, dexterity_audit.hpp): writes
// <sub>/<design>_audit.csv, sets d["audit"] (with the verdicts per status and how many the audit
// contradicted) and returns the report paragraph.
report::Document writeAudit(const Model& m, const DexterityOptions& options,
                            const DexterityAudit& a, const std::string& sub, Writer& out,
                            nlohmann::ordered_json& d);

}  // namespace armstudy::dexterity
