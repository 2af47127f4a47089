#include "stages/calibration/calibration_stage.hpp"

#include <omp.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "calibration/arm_view.hpp"
#include "calibration/identification_report.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/parallel_for.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/urdf_io.hpp"
#include "report/markdown.hpp"
#include "stages/calibration/calibration_report.hpp"

namespace armstudy::calibration {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

namespace {

// ---------------------------------------------------------------------------------------------
// The design an entry evaluates
// ---------------------------------------------------------------------------------------------

// Design names allow letters, digits, '_', '-' and '.'; variant names also hold '+' and '='.
std::string fileSafe(const std::string& name) {
  std::string s = name;
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) c = '_';
  return s;
}

// The design file text of a study variant: the variant's Model (its base design with the
// overrides set), named by a file-safe form of the variant name, through the design writer. The
// calibrated copy of a variant is the variant's Model with the fitted values applied.
std::string variantDesignText(const StudyDesign& d, const std::string& name) {
  Model v = d.model;
  v.name = name;
  const std::string text = "# Study variant '" + d.model.name + "' of " + d.model.file +
                           " (armstudy [[calibration]] stage).\n" + designToToml(v);
  parseDesign(text, name + ".toml");  // a valid design
  return text;
}

// ---------------------------------------------------------------------------------------------
// One entry
// ---------------------------------------------------------------------------------------------

struct Work {
  const CalibrationEntry* entry = nullptr;
  const StudyDesign* design = nullptr;
  Model model;               // the design as evaluated (variants: file = the written variant text)
  std::string variant_text;  // variants only
  std::string folder;        // <output>/calibration/<name>
  std::unique_ptr<ArmProblem> problem;
  std::optional<ArmDiagnosis> diagnosis;
};

// Phase 1 (no files): the diagnosis. InputErrors the loader could not foresee (too few rows for
// the model's parameters) surface here, before anything of the stage is written.
void diagnose(Work& w) {
  const CalibrationEntry& e = *w.entry;
  w.problem = e.kind->problem(w.model, e.data, e.problem);
  w.diagnosis = e.fit ? diagnoseArm(*w.problem, e.options) : compareArm(*w.problem, e.options);
}

std::string relativeTo(const std::string& path, const std::string& root) {
  return fs::path(path).lexically_relative(fs::path(root)).generic_string();
}

// Per effect the kind's summary lists: whether it was significant in the first ranking.
std::vector<std::uint8_t> significantFlags(const std::vector<std::string>& effects,
                                           const ArmDiagnosis& d) {
  std::vector<std::uint8_t> flags;
  for (const std::string& name : effects) {
    bool sig = false;
    for (const ArmCandidate& c : d.ranking) sig = sig || (c.name == name && c.significant);
    flags.push_back(sig ? 1 : 0);
  }
  return flags;
}

// The files and summary of an entry; returns the calibrated design's path (empty: none).
std::string writeEntryFiles(const Work& w, const std::string& cal_dir, EntrySummary& s) {
  const CalibrationEntry& e = *w.entry;
  const Kind& kind = *e.kind;
  std::string cal_path;
  const ArmDiagnosis& d = *w.diagnosis;
  const ArmProblem& P = *w.problem;
  if (e.fit) {
    std::vector<std::pair<std::string, std::string>> extra;
    if (e.log) {
      IdentificationInput in;
      in.reference_source = e.reference.source;
      in.reference = e.reference.values;
      const IdentificationReport ir = identificationReport(d, P, w.model, *e.data.trajectory, in);
      extra = {{"identification.md", ir.markdown}, {"residuals_before_after.svg", ir.svg}};
      s.reports.push_back({"identification.md", report::Document().markdown(ir.markdown)});
      s.extra_metrics = ir.metrics;
      s.answers = ir.answer;
    }
    const ArmFitFiles f = writeArmFit(d, P, w.model, w.folder, "", false, extra);
    cal_path = f.calibrated_design_path;
    s.notes = f.notes;
  } else {
    writeArmReport(d, P, ArmReportOptions{w.folder, "compare", {}, false}, "");
  }
  s.unit = P.fit_unit;
  s.noise_estimate = d.noise_estimate;
  s.as_designed_rmse = kind.summaryRmse(d.as_designed);
  s.as_designed_flagged = d.as_designed_map.flagged();
  s.bins = static_cast<int>(d.as_designed_map.bins.size());
  for (const ArmFit& m : d.ladder)
    s.ladder.push_back({m.label, m.n_params, m.train_rmse, m.heldout_rmse});
  s.catalogue = kind.summaryEffects(P);
  s.significant = significantFlags(s.catalogue, d);
  s.added = addedAfterBase(d, P);
  s.warnings = d.warnings;
  s.view = residualViewClouds(d, P, w.model, e.name);
  if (kind.remaindersWarn())
    for (const ArmRemainder& r : d.remainders) s.remainders.push_back(r.text());
  s.verdict = e.fit ? d.verdict : "compare only";
  if (e.fit) {
    s.rmse_before = baseFit(d, P).heldout_rmse;
    s.rmse_after = d.rmse_after;
    s.final_params = d.final_fit.params;
  }
  if (e.fit && !cal_path.empty()) {
    const Model cal = loadDesign(cal_path);
    const auto Pc = kind.problem(cal, e.data, e.problem);
    const ArmDiagnosis c = compareArm(*Pc, e.options);
    writeArmReport(
        c, *Pc, ArmReportOptions{cal_dir, "compare", {}, false, ShownDesign::calibrated_copy}, "");
    s.calibrated_rmse = kind.summaryRmse(c.as_designed);
    s.calibrated_flagged = c.as_designed_map.flagged();
  }
  return cal_path;
}

// Phase 2: the files (what `armstudy fit|compare` writes, plus the compare of the calibrated copy
// in calibrated/) and the entry summary.
EntrySummary writeEntry(Work& w, const std::string& output_dir) {
  const CalibrationEntry& e = *w.entry;
  EntrySummary s;
  s.name = e.name;
  s.kind = e.kind->name();
  s.design = e.design;
  s.data_file = e.data_file;
  s.data_hash = e.dataHash();
  s.joint = e.problem.joint;
  s.mode = e.fit ? "fit" : "compare";
  s.rmse_before = s.rmse_after = s.calibrated_rmse = std::nan("");
  // A fresh folder: history.csv is appended to by the reports, so a leftover of an interrupted
  // run must not leak into this one.
  fs::remove_all(w.folder);
  fs::create_directories(w.folder);
  if (!w.variant_text.empty()) writeFileAtomic(w.model.file, w.variant_text);
  const std::string cal_dir = w.folder + "/calibrated";

  const std::string cal_path = writeEntryFiles(w, cal_dir, s);
  if (!cal_path.empty()) s.calibrated_design = relativeTo(cal_path, w.folder);
  for (report::ReportFile& r : s.reports) r.path = relativeTo(w.folder + "/" + r.path, output_dir);

  // Every file of the entry folder, sorted (the reports list theirs in different forms).
  const std::string summary_rel = relativeTo(w.folder + "/summary.json", output_dir);
  for (const auto& f : fs::recursive_directory_iterator(w.folder))
    if (f.is_regular_file()) s.files.push_back(relativeTo(f.path().string(), output_dir));
  s.files.push_back(summary_rel);
  std::sort(s.files.begin(), s.files.end());
  writeFileAtomic(w.folder + "/summary.json", entrySummaryToJson(s));
  return s;
}

// ---------------------------------------------------------------------------------------------
// Checkpoints: a unit is one entry; what is saved is its summary, its report documents (as their
// Markdown: a document and its Markdown give the same page) plus the content hash of every file it
// wrote, so a resumed run reuses the entry only when its files are still intact.
// ---------------------------------------------------------------------------------------------

std::string unitId(const CalibrationEntry& e) { return "calibration-" + e.name; }

std::string checkpointBytes(const EntrySummary& s, const std::string& output_dir) {
  ordered_json j;
  j["summary"] = entrySummaryToJson(s);
  j["view"] = viewCloudsToJson(s.view);
  ordered_json reports = ordered_json::array();
  for (const report::ReportFile& r : s.reports)
    reports.push_back({{"path", r.path}, {"markdown", report::toMarkdown(r.doc)}});
  j["reports"] = reports;
  ordered_json h = ordered_json::object();
  for (const std::string& f : s.files) h[f] = fileHash((fs::path(output_dir) / f).string());
  j["hashes"] = h;
  return j.dump();
}

// A saved unit's entry summary, when every file it lists is still intact.
std::optional<EntrySummary> resumeEntry(const std::string& bytes, const std::string& output_dir) {
  try {
    const ordered_json j = ordered_json::parse(bytes);
    EntrySummary s = entrySummaryFromJson(j.at("summary").get<std::string>());
    s.view = viewCloudsFromJson(j.at("view").get<std::string>());
    for (const ordered_json& r : j.at("reports"))
      s.reports.push_back({r.at("path").get<std::string>(),
                           report::Document().markdown(r.at("markdown").get<std::string>())});
    const ordered_json& h = j.at("hashes");
    if (h.size() != s.files.size()) return std::nullopt;
    for (const std::string& f : s.files) {
      const fs::path p = fs::path(output_dir) / f;
      if (!fs::is_regular_file(p) || fileHash(p.string()) != h.at(f).get<std::string>())
        return std::nullopt;
    }
    return s;
  } catch (const std::exception&) {
    return std::nullopt;  // unreadable unit: run the entry again
  }
}

// ---------------------------------------------------------------------------------------------
// Metrics and the stage report
// ---------------------------------------------------------------------------------------------

void addMetrics(const EntrySummary& s, StudyMetrics& M) {
  const std::string p = "calibration/" + s.name + "/";
  M.scalars[p + "as_designed_rmse"] = s.as_designed_rmse;
  M.scalars[p + "as_designed_flagged_bins"] = s.as_designed_flagged;
  M.scalars[p + "noise_estimate"] = s.noise_estimate;
  if (s.mode != "fit") return;
  M.scalars[p + "rmse_before"] = s.rmse_before;
  M.scalars[p + "rmse_after"] = s.rmse_after;
  M.scalars[p + "calibrated_rmse"] = s.calibrated_rmse;
  M.scalars[p + "calibrated_flagged_bins"] = s.calibrated_flagged;
  for (std::size_t k = 0; k < s.ladder.size(); ++k)
    M.scalars[p + "ladder/" + std::to_string(k) + "/heldout_rmse"] = s.ladder[k].heldout_rmse;
  for (std::size_t k = 0; k < s.added.size(); ++k)
    M.scalars[p + "added/" + s.added[k]] = static_cast<double>(k + 1);
  for (const FittedParameter& f : s.final_params) M.scalars[p + "param/" + f.key] = f.value;
  for (const auto& [k, v] : s.extra_metrics) M.scalars[p + k] = v;
  std::vector<std::uint8_t> added(s.catalogue.size(), 0);
  for (std::size_t k = 0; k < s.catalogue.size(); ++k)
    added[k] = std::find(s.added.begin(), s.added.end(), s.catalogue[k]) != s.added.end();
  M.flags[p + "added"] = added;
  M.flags[p + "significant"] = s.significant;
}

// An entry's answer (StageResult::answer): the effects the measurements named, in the order they
// were added, and how far the held-out error fell; or its verdict when nothing was added.
std::string entryAnswer(const EntrySummary& e) {
  std::string a = "`" + e.name + "` (" + e.kind + ", `" + e.design + "`): ";
  if (e.added.empty() || !std::isfinite(e.rmse_before) || !std::isfinite(e.rmse_after))
    return a + e.verdict;
  for (std::size_t k = 0; k < e.added.size() && k < 4; ++k)
    a += (k ? ", " : "adding ") + effectWords(e.added[k]);
  if (e.added.size() > 4) a += " and " + std::to_string(e.added.size() - 4) + " more";
  const ShownUnit u = shownUnit(e.unit);
  const auto v = [&](double x) { return u.decimals < 0 ? formatG(x, 3) : shown(x, u); };
  a += " lowers the held-out RMSE from " + v(e.rmse_before) + " to " + v(e.rmse_after) + " " +
       u.unit;
  if (e.rmse_after > 0) a += " (" + formatG(e.rmse_before / e.rmse_after, 3) + "x lower)";
  return a + ".";
}

}  // namespace

StageResult runCalibrationStage(const StageContext& ctx,
                                const std::vector<CalibrationEntry>& entries,
                                std::vector<EntrySummary>* results) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  const int n = static_cast<int>(entries.size());
  const std::string dir = ctx.output_dir + "/calibration";
  std::vector<Work> work(n);
  std::vector<std::optional<EntrySummary>> done(n);
  UnitBatch batch;
  for (int i = 0; i < n; ++i) {
    Work& w = work[i];
    w.entry = &entries[i];
    for (const StudyDesign& d : ctx.study.designs)
      if (d.model.name == entries[i].design) w.design = &d;
    ARMSTUDY_CHECK(w.design,
                   "calibration entry '" + entries[i].name + "' names a design the study has");
    w.folder = dir + "/" + entries[i].name;
    w.model = w.design->model;
    if (!w.design->overrides.empty()) {
      w.model.name = fileSafe(w.design->model.name);
      w.variant_text = variantDesignText(*w.design, w.model.name);
      w.model.file = w.folder + "/" + w.model.name + ".toml";
      w.model.file_hash = contentHash(w.variant_text);
    }
    batch.ids.push_back(unitId(entries[i]));
  }
  // An entry's files (they name the output folder) are part of its result: not portable.
  batch.portable = false;
  batch.load = [&](std::size_t i, const std::string& bytes) {
    done[i] = resumeEntry(bytes, ctx.output_dir);
    return done[i].has_value();
  };
  // Units: one per entry, each sequential; exceptions are carried out of the parallel loops and
  // the first one in entry order is rethrown.
  batch.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& unit_done) {
    const int m = static_cast<int>(todo.size());
    parallelFor(m, ctx.threads, [&](int k) { diagnose(work[todo[k]]); });
    parallelFor(m, ctx.threads, [&](int k) {
      const std::size_t i = todo[k];
      done[i] = writeEntry(work[i], ctx.output_dir);
      unit_done(i, checkpointBytes(*done[i], ctx.output_dir));
    });
  };
  sum.units_resumed = ctx.units.run(batch);

  std::vector<EntrySummary> entry_summaries;
  ordered_json js;
  js["study"] = ctx.study.name;
  js["entries"] = ordered_json::array();
  for (int i = 0; i < n; ++i) {
    entry_summaries.push_back(*done[i]);
    sum.files.insert(sum.files.end(), done[i]->files.begin(), done[i]->files.end());
    js["entries"].push_back(ordered_json::parse(entrySummaryToJson(*done[i])));
    addMetrics(*done[i], sum.metrics);
    sum.view.insert(sum.view.end(), done[i]->view.begin(), done[i]->view.end());
    sum.reports.insert(sum.reports.end(), done[i]->reports.begin(), done[i]->reports.end());
    sum.answer.push_back(entryAnswer(*done[i]));
    for (const std::string& a : done[i]->answers)
      sum.answer.push_back("`" + done[i]->name + "`, " + a);
    for (const std::string& r : done[i]->remainders)
      sum.warnings.push_back("`" + done[i]->name + "`: " + r);
    if (const std::string w = checkRunWarning(*done[i]); !w.empty())
      sum.warnings.push_back("`" + done[i]->name + "`: " + w);
  }
  if (!sum.view.empty()) {
    sum.view_about =
        "The points are the data rows' TCP positions in the world frame (measured for TCP data, "
        "the design's forward kinematics of the logged joint positions for joint logs), coloured "
        "by the residual's magnitude (measured - predicted, each map its channel and unit) or by "
        "whether the row's workspace cell is flagged; the arm (joint frame origins, base to tool) "
        "stands at the row of the map's largest residual.";
    sum.view_value_label = "residual";
  }
  report::Document report = stageReport(ctx.study.name, entry_summaries, "calibration");
  writeFileAtomic(dir + "/report.md", report::toMarkdown(report));
  sum.reports.push_back({"calibration/report.md", std::move(report)});
  writeFileAtomic(dir + "/summary.json", js.dump(2) + "\n");
  sum.files.push_back("calibration/report.md");
  sum.files.push_back("calibration/summary.json");
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (results) *results = std::move(entry_summaries);
  return sum;
}

}  // namespace armstudy::calibration
