#pragma once
// The harvest stage's outputs (private to stages/harvest): tables, CSV files, profile plots and
// the holding-load grid of one design, from its DesignResult (see harvest_stage.hpp).
#include <array>
#include <string>
#include <vector>

#include "report/document.hpp"
#include "report/plot.hpp"
#include "report/view3d.hpp"
#include "stages/harvest/harvest_stage.hpp"
#include "study/writer.hpp"

namespace armstudy::harvest {

// Worst (largest value) check of joint i and quantity q over the evaluated fruits.
struct JointAggregate {
  double peak_effort = 0;
  std::array<QuantityCheck, kDriveQuantityCount> worst;  // with friction
  double peak_current_no_friction = 0;
  // Max over the evaluated fruits of the share of the peak current friction adds,
  // (peak |I_f| - peak |I_nf|) / peak |I_f| (negative where friction lowers the peak).
  double friction_share = 0;
  bool has_friction_share = false;
  int exceeded_fruits = 0;  // fruits where any check of this joint failed (with friction)
  bool has_drive = false;
};
std::vector<JointAggregate> aggregate(const Model& model, const DesignResult& d);

std::string marginText(const QuantityCheck& c);
std::string limitText(const QuantityCheck& c, int decimals);
// "j3 peak_current at 0.42 s", or "feasible".
std::string failureText(const Model& model, const DriveFeasibility& r);
// <design>_fruits.csv: one row per fruit; <design>_fruit<k>_profile.csv: one row per sample.
std::string fruitCsv(const Model& model, const DesignResult& d);
std::string profileCsv(const Model& model, const FruitResult& f, double dt);
// One series per joint, every `stride`-th sample (plots stay small).
std::vector<report::PlotSeries> profileSeries(const Model& model,
                                              const std::vector<JointVector>& rows, double dt,
                                              const std::string& suffix, int stride);

// A joint limit for a sentence: "+120 deg" (revolute), "-0.500 m" (prismatic).
std::string jointLimitText(const Model& model, int joint, double q);
// The topic of the design's assumption lines about a drive quantity's limit ("current limits",
// "max_motor_speed", "max_voltage"; model/model_notes.hpp notes::about).
const char* assumptionTopic(DriveQuantity q);
// The design's assumption lines the fruit's failure rests on (the limit that stopped it), none
// when it was picked or failed for another reason.
std::vector<std::string> failureAssumptions(const Model& model, const FruitResult& f);

// What became of a fruit: "picked" (tracked, every drive within its limits), the drive check that
// failed first ("drive limit: j8 motor_speed"), the joint whose limit stopped the tracking
// ("joint limit: j3"), or the planning / tracking status that stopped it.
std::string fruitOutcome(const Model& model, const FruitResult& f);
// Every fruit of every design at its position (y along the row, z up, world frame), marked by its
// outcome; one panel per design on the same axes, one colour per outcome in every panel.
report::Drawing fruitOutcomeFigure(const std::vector<const Model*>& models,
                                   const std::vector<const DesignResult*>& results);
// Writes fruitOutcomeFigure as harvest/fruits.svg; returns the report part that shows it.
report::Document writeFruitOutcomeFigure(const std::vector<const Model*>& models,
                                         const std::vector<const DesignResult*>& results,
                                         Writer& out);

// The static holding load over the [harvest.grid]: <design>_holding.vti and, for a grid with two
// axes of more than one value, status and current-ratio maps (.png raw, .svg with axes). Adds the
// holding metrics to M; returns the report part and the numbers for summary.json.
struct HoldingSummary {
  long points = 0;
  int reachable = 0, limited = 0;
  double max_ratio = 0;
  report::Document doc;
  // The grid for the study's 3-D view: its reachable points by status (the map's colours) and by
  // the revolute joints' largest current ratio, with the arm at its zero pose.
  report::ViewCloud view;
};
HoldingSummary writeHoldingGrid(const Model& model, const HarvestGrid& g, const DesignResult& d,
                                Writer& out, StudyMetrics& M);

}  // namespace armstudy::harvest
