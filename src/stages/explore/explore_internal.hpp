#pragma once
// Internal to src/stages/explore: the candidate evaluator and searches, and the report.
#include <map>
#include <string>
#include <vector>

#include "io/variant.hpp"
#include "stages/explore/explore.hpp"
#include "study/checkpoint.hpp"

namespace armstudy::explore {

// Evaluates candidates (each one work unit "explore/<name>": its objective metric values) by
// running the chosen stages on a study holding only that candidate, and runs the searches.
class Evaluator {
 public:
  Evaluator(const StageContext& ctx, const ExploreOptions& o);
  // Evaluates the candidates with these parameter values (or the base design itself when
  // `base`); returns their indices in candidates(). Known candidates are not evaluated again.
  std::vector<std::size_t> evaluate(const std::vector<std::vector<double>>& params, bool base);
  void searchGrid();
  void searchOptimise();
  // Runs the stages on one design, writing their files under `dir` (front designs' maps), with
  // the colour scales reaching at least `scale_tops` (RunOptions::shared_scale_tops).
  StageResult runStages(const Model& m, const Overrides& ov, const std::string& dir,
                        const std::map<std::string, double>& scale_tops = {}) const;

  const std::vector<Candidate>& candidates() const { return cands_; }
  const std::string& status() const { return status_; }
  long unitsResumed() const { return units_resumed_ + inner_resumed_; }
  long skipped() const { return skipped_; }

 private:
  static std::string stageName(const StudySection& s);
  Study candidateStudy(const Model& m, const Overrides& ov) const;
  std::vector<double> metricValues(const Model& m, const StudyMetrics& metrics) const;
  bool parametersFeasible(const std::vector<double>& params, double& violation) const;
  double metricViolation(const std::vector<double>& values) const;
  std::vector<double> baseParams() const;
  Overrides overridesOf(const std::vector<double>& params) const;
  std::vector<double> snap(const std::vector<double>& x01) const;
  double score(const std::vector<double>& x01);

  const StageContext& ctx_;
  const ExploreOptions& o_;
  RunOptions inner_options_;
  std::vector<StudySection> sections_;
  std::string scratch_;
  std::vector<Candidate> cands_;
  std::map<std::string, std::size_t> by_name_;
  std::string status_;
  long units_resumed_ = 0, inner_resumed_ = 0, skipped_ = 0;
};

}  // namespace armstudy::explore
