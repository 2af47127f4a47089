#pragma once
// Regression checks (docs/regression.md): a baseline records a study's summary metrics; a check
// re-runs the study and compares metric by metric with tolerances declared in the study.
#include <string>
#include <vector>

#include "study/metrics.hpp"

namespace armstudy {

inline constexpr int kBaselineFormatVersion = 1;

// One tolerance rule from the study's [[regression.tolerance]] list. `metric` is a glob ('*'
// matches any run of characters, including '/'); the first matching rule wins.
struct ToleranceRule {
  std::string metric;
  double abs = 0;  // |now - baseline| <= abs + rel * |baseline| passes (scalars)
  double rel = 0;
  int flips = 0;  // per-pose flag metrics: number of entries allowed to change
  int line = 0;   // where it was declared, for messages
};

struct RegressionSpec {
  std::string baseline_path;                       // resolved path of the baseline file
  std::vector<ToleranceRule> rules;                // in declaration order
  ToleranceRule fallback{"*", 1e-12, 1e-9, 0, 0};  // for metrics no rule matches
  const ToleranceRule& ruleFor(const std::string& metric) const;
};

struct Baseline {
  int format_version = kBaselineFormatVersion;
  std::string study;  // study name it belongs to
  std::string armstudy_version;
  std::string git_revision;
  StudyMetrics metrics;
};

std::string baselineToJson(const Baseline& b);
// Parses a baseline; throws InputError(file, ...) for malformed JSON, an unknown format version,
// or a baseline of another study (`expected_study`).
Baseline parseBaseline(const std::string& text, const std::string& file,
                       const std::string& expected_study);

enum class Verdict { Pass, Fail, Missing, New };
const char* toString(Verdict v);

struct CheckRow {
  std::string metric;
  bool is_flags = false;
  double baseline = 0, now = 0;  // scalars; for flags: counts of set entries
  double abs_tol = 0, rel_tol = 0;
  int flips = 0, flips_allowed = 0;
  std::vector<std::size_t> flipped;  // indices of flipped entries (first few)
  Verdict verdict = Verdict::Pass;
};

struct CheckResult {
  std::vector<CheckRow> rows;  // sorted by metric name
  bool passed() const;
  int failures() const;
};

// InputError(spec.baseline_path, "flags.<metric>") when a per-pose flag string of the baseline
// has another length than the run's.
CheckResult compareToBaseline(const Baseline& baseline, const StudyMetrics& now,
                              const RegressionSpec& spec);
std::string checkTable(const CheckResult& r, bool only_moved);  // human-readable table
std::string checkJson(const CheckResult& r);                    // for CI

}  // namespace armstudy
