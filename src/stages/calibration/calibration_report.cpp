// The [[calibration]] stage's report.md (stages/calibration/calibration_report.hpp).
#include "stages/calibration/calibration_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <tuple>

#include "report/markdown.hpp"

namespace armstudy::calibration {

namespace fs = std::filesystem;

namespace {

// A calibrated copy whose RMSE against the same data is within this fraction of the fit's training
// RMSE reproduces the fit: its check run's figures repeat the after figures and are not shown.
constexpr double kCheckRunRepeatsFit = 0.01;

// Whether the calibrated copy's check run reproduces the fit: its RMSE against the same data is
// the fit's training RMSE within kCheckRunRepeatsFit (the copy holds every fitted value).
bool checkRunRepeatsFit(const EntrySummary& s) {
  if (s.mode != "fit" || s.calibrated_design.empty() || s.ladder.empty()) return false;
  const double fit = s.ladder.back().train_rmse;
  return std::isfinite(s.calibrated_rmse) && std::isfinite(fit) &&
         std::abs(s.calibrated_rmse - fit) <= kCheckRunRepeatsFit * fit;
}

// The figures of an entry (paths relative to the stage folder) in reading order: the error ladder,
// the residuals against their predictions (before and after in one figure), then each figure of
// the model before the fit followed by its counterpart after it, then the calibrated copy's check
// run in the same order, then any other figure. Figures that repeat others go to `folded` instead:
// the check run's when it reproduces the fit (checkRunRepeatsFit), and the after figures over the
// operating variables and the workspace when the fit leaves no bin flagged (their residuals lie
// inside the thresholds everywhere; the residuals against their predictions show before and after
// on one scale).
struct EntryFigures {
  std::vector<std::string> shown, folded;
};
EntryFigures entryFigures(const EntrySummary& s, const std::string& stage_dir) {
  EntryFigures out;
  const bool fold_check = checkRunRepeatsFit(s);
  const bool fold_after = fold_check && s.calibrated_flagged == 0;
  for (const std::string& f : s.files) {
    if (fs::path(f).extension() != ".svg") continue;
    const std::string rel = fs::path(f).lexically_relative(stage_dir).generic_string();
    const bool check = rel.rfind(s.name + "/calibrated/", 0) == 0;
    const bool after = rel.rfind(s.name + "/plots/after_", 0) == 0;
    (fold_check && check) || (fold_after && after) ? out.folded.push_back(rel)
                                                   : out.shown.push_back(rel);
  }
  const auto rank = [&](const std::string& f) {
    const std::string rest = f.substr(s.name.size() + 1);
    const bool check = rest.rfind("calibrated/", 0) == 0;
    const std::string name = fs::path(rest).filename().string();
    int order = 3;
    std::string key = name;
    if (name == "error_ladder.svg") {
      order = 0;
    } else if (name.rfind("residual_vs_predicted_", 0) == 0) {
      order = 1;
    } else if (name.rfind("before_", 0) == 0 || name.rfind("after_", 0) == 0) {
      order = 2;
      const bool after = name[0] == 'a';
      key = name.substr(after ? 6 : 7) + (after ? "/1" : "/0");
    }
    return std::make_tuple(check, order, key);
  };
  for (auto* v : {&out.shown, &out.folded})
    std::stable_sort(v->begin(), v->end(),
                     [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
  return out;
}

// The entry's figures: what is folded (said and linked), then the figures shown.
report::Document entryFiguresDocument(const EntrySummary& s, const std::string& stage_dir) {
  const EntryFigures figs = entryFigures(s, stage_dir);
  const ShownUnit u = shownUnit(s.unit);
  const auto q = [&](double v) { return shown(v, u) + " " + u.unit; };
  report::Document doc;
  if (checkRunRepeatsFit(s))
    doc.paragraph("The calibrated copy reproduces the fit against the same data (RMSE " +
                  q(s.calibrated_rmse) + ", the fit's training RMSE " +
                  q(s.ladder.back().train_rmse) + "): its figures in [`" + s.name +
                  "/calibrated/`](" + s.name +
                  "/calibrated/) repeat the after figures and are not shown.");
  std::string after;
  for (const std::string& f : figs.folded) {
    if (f.rfind(s.name + "/plots/after_", 0) != 0) continue;
    const std::string stem = fs::path(f).stem().string().substr(6);  // "after_" dropped
    after += (after.empty() ? "" : ", ") + ("[" + stem + "](" + f + ")");
  }
  if (!after.empty())
    doc.paragraph("After the fit no bin of the residual map is flagged (" +
                  std::to_string(s.calibrated_flagged) + " of " + std::to_string(s.bins) +
                  "): the after figures show residuals inside their thresholds everywhere and are "
                  "linked, not shown: " +
                  after + ".");
  for (const std::string& f : figs.shown) doc.figures({{f, f}});
  return doc;
}

// The entry's heading and what it compared: kind, design, data, mode, noise, as designed.
void entryHead(const EntrySummary& s, report::Document& doc) {
  const ShownUnit u = shownUnit(s.unit);
  const auto q = [&](double v) { return shown(v, u) + " " + u.unit; };
  std::ostringstream p;
  p << "Kind " << s.kind << (s.joint.empty() ? "" : " (drive " + s.joint + ")") << ", design `"
    << s.design << "`, data `" << s.data_file << "` (" << s.data_hash << "), mode " << s.mode
    << ". Noise estimate " << q(s.noise_estimate) << "; as designed RMSE " << q(s.as_designed_rmse)
    << ", flagged bins " << s.as_designed_flagged << " of " << s.bins << ".";
  std::vector<std::vector<std::string>> rows;
  for (const LadderStep& l : s.ladder)
    rows.push_back({l.label.rfind('+', 0) == 0 ? "+ " + effectWords(l.label.substr(1)) : l.label,
                    std::to_string(l.n_params), shown(l.train_rmse, u), shown(l.heldout_rmse, u)});
  doc.heading(2, s.name).paragraph(p.str()).table(
      {"model", ">params", ">train RMSE [" + u.unit + "]", ">held-out RMSE [" + u.unit + "]"},
      std::move(rows));
}

// A fit's verdict, what it added, the calibrated copy and the fitted parameters.
void entryFit(const EntrySummary& s, report::Document& doc) {
  const ShownUnit u = shownUnit(s.unit);
  const auto q = [&](double v) { return shown(v, u) + " " + u.unit; };
  std::string added;
  for (const auto& a : s.added) added += (added.empty() ? "" : ", ") + effectWords(a);
  std::ostringstream p;
  p << "Verdict: " << s.verdict << ". Added: " << (added.empty() ? "none" : added)
    << ". Held-out RMSE " << shown(s.rmse_before, u) << " -> " << q(s.rmse_after);
  if (s.rmse_after > 0 && !s.added.empty())
    p << " (x" << report::fixed(s.rmse_before / s.rmse_after, 2) << " lower)";
  if (s.calibrated_design.empty()) {
    p << ". No calibrated copy";
    for (const auto& n : s.notes) p << "; " << n;
    p << ".";
  } else {
    p << ". Calibrated copy `" << s.name << "/" << s.calibrated_design
      << "` against the same data: RMSE " << q(s.calibrated_rmse) << ", flagged bins "
      << s.calibrated_flagged << " of " << s.bins << " (as designed: " << s.as_designed_flagged
      << ").";
  }
  doc.paragraph(p.str());
  if (!s.extra_metrics.empty())
    doc.paragraph(
        "Per joint (held out by time block), the fitted values beside the reference and the "
        "friction coefficients over the smooth-sign width: `" +
        s.name + "/identification.md`; residuals before and after on one scale: `" + s.name +
        "/residuals_before_after.svg`.");
  std::vector<std::vector<std::string>> rows;
  for (const FittedParameter& f : s.final_params)
    rows.push_back({effectWords(f.key), shown(f.value, shownUnit(f.unit)), shownUnit(f.unit).unit,
                    "[" + shown(f.ci_low, shownUnit(f.unit)) + ", " +
                        shown(f.ci_high, shownUnit(f.unit)) + "]"});
  if (!rows.empty()) doc.table({"parameter", ">value", "unit", ">95 % interval"}, std::move(rows));
}

}  // namespace

std::string checkRunWarning(const EntrySummary& s) {
  if (s.mode != "fit" || s.calibrated_design.empty() || s.ladder.empty() ||
      !std::isfinite(s.calibrated_rmse) || checkRunRepeatsFit(s))
    return "";
  const ShownUnit u = shownUnit(s.unit);
  const auto q = [&](double v) { return shown(v, u) + " " + u.unit; };
  std::string held;
  for (const std::string& n : s.notes)
    if (n.find("not stored") != std::string::npos) held += (held.empty() ? "" : "; ") + n;
  return "the calibrated copy `" + s.name + "/" + s.calibrated_design +
         "` does not reproduce the fit: RMSE " + q(s.calibrated_rmse) +
         " against the same data, the fit's " + q(s.ladder.back().train_rmse) + " (training)" +
         (held.empty() ? std::string(".") : "; " + held + ".");
}

report::Document stageReport(const std::string& study, const std::vector<EntrySummary>& entries,
                             const std::string& stage_dir) {
  report::Document doc;
  doc.heading(1, "Model versus measurement: " + study)
      .paragraph(
          "Each entry compares a design's model with measured data, ranks the candidate effects "
          "that could be missing by cross-validated error, adds them as asked, writes a "
          "calibrated copy of the design and compares that copy with the same data "
          "(docs/calibration.md, \"As a study stage\"). RMSE in the unit of each entry; "
          "held-out = k-fold cross-validation.");
  for (const EntrySummary& s : entries) {
    entryHead(s, doc);
    if (s.mode == "fit") entryFit(s, doc);
    for (const auto& n : s.notes) doc.paragraph("Note: " + n);
    for (const auto& x : s.warnings) doc.paragraph("Warning: " + x);
    doc.paragraph("Reports: `" + s.name + "/result.json`, plots in `" + s.name + "/plots/`" +
                  (s.mode == "fit"
                       ? ", the calibrated copy's comparison in `" + s.name + "/calibrated/`"
                       : std::string()) +
                  ".");
    doc.append(entryFiguresDocument(s, stage_dir));
  }
  return doc;
}

}  // namespace armstudy::calibration
