#include "calibration/drive_report.hpp"
#include "calibration/history.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "calibration/svg_plot.hpp"
#include "common/errors.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json statsJson(const ChannelStats& s, const char* unit) {
  return {{"unit", unit}, {"rmse", s.rmse}, {"bias", s.bias}, {"max", s.max_abs}, {"n", s.n}};
}

json paramsJson(const std::vector<FittedParameter>& ps) {
  json a = json::array();
  for (const auto& p : ps)
    a.push_back({{"key", p.key}, {"value", p.value}, {"unit", p.unit},
                 {"ci95", {finite(p.ci_low), finite(p.ci_high)}}, {"at_bound", p.at_bound}});
  return a;
}

json fitJson(const ModelFit& m) {
  json e = json::array();
  for (auto x : m.effects) e.push_back(drive::toString(x));
  return {{"label", m.label}, {"effects", e}, {"n_params", m.n_params}, {"train_rmse", finite(m.train_rmse)},
          {"heldout_rmse", finite(m.heldout_rmse)}, {"region_heldout_rmse", finite(m.region_heldout_rmse)},
          {"aic", finite(m.aic)}, {"bic", finite(m.bic)}, {"params", paramsJson(m.params)}};
}

json rankingJson(const std::vector<Candidate>& r) {
  json a = json::array();
  for (const auto& c : r) {
    json j = {{"effect", drive::toString(c.effect)}, {"status", c.status}, {"significant", c.significant},
              {"pattern", effectInfo(c.effect).pattern}, {"warnings", c.warnings}};
    if (c.status == "ok") {
      j["heldout_rmse"] = finite(c.fit.heldout_rmse);
      j["region_heldout_rmse"] = finite(c.fit.region_heldout_rmse);
      j["train_rmse"] = finite(c.fit.train_rmse);
      j["improvement"] = finite(c.improvement);
      j["t_statistic"] = finite(c.t_statistic);
      j["aic"] = finite(c.fit.aic);
      j["bic"] = finite(c.fit.bic);
      j["params"] = paramsJson(c.fit.params);
    } else {
      j["heldout_rmse"] = nullptr;
      j["improvement"] = nullptr;
      j["params"] = json::array();
    }
    a.push_back(j);
  }
  return a;
}

json regionsJson(const ResidualMap& m) {
  json a = json::array();
  for (const auto& b : m.bins)
    if (b.flagged)
      a.push_back({{"speed", {b.speed_lo, b.speed_hi}}, {"load", {b.load_lo, b.load_hi}}, {"n", b.n},
                   {"n_eff", b.n_eff}, {"mean_residual", b.mean}, {"threshold", b.threshold}});
  return a;
}

std::string stageTitle(const std::string& stage, const ModelFit& m) { return stage + ": " + m.label; }

void writePlots(const std::string& dir, const std::string& stage, const ModelFit& m, const Comparison& cmp,
                const DriveData& data, double noise, std::vector<std::string>& files) {
  const std::string rel = "plots/" + stage + "_";
  auto put = [&](const std::string& name, const std::string& svg) {
    writeFileAtomic((fs::path(dir) / (rel + name)).string(), svg);
    files.push_back(rel + name);
  };
  {
    PlotSpec p;
    p.title = "measured vs predicted current (" + stageTitle(stage, m) + ")";
    p.x_label = "predicted current [A]";
    p.y_label = "measured current [A]";
    p.diagonal = true;
    p.series.push_back({"rows", m.predicted, data.current, "#1f77b4", false, true});
    put("measured_vs_predicted.svg", svgPlot(p));
  }
  auto residualVs = [&](const std::string& name, const std::string& xl, const std::vector<double>& x) {
    PlotSpec p;
    p.title = "residual vs " + name + " (" + stageTitle(stage, m) + ")";
    p.x_label = xl;
    p.y_label = "current residual, measured - predicted [A]";
    p.h_lines = {0.0, noise, -noise};
    p.series.push_back({"rows", x, m.residual, "#d62728", false, true});
    put("residual_vs_" + name + ".svg", svgPlot(p));
  };
  residualVs("speed", "motor speed [rad/s]", data.speed);
  residualVs("load", "load torque [N m]", data.load);
  if (data.hasTemperature()) residualVs("temperature", "temperature [deg C]", data.temperature);
  HeatmapSpec h;
  h.title = "mean residual per bin (" + stageTitle(stage, m) + ")";
  h.x_label = "motor speed [rad/s]";
  h.y_label = "|load torque| [N m]";
  h.value_label = "mean residual [A]";
  h.x_min = cmp.map.speed_edges.front();
  h.x_max = cmp.map.speed_edges.back();
  h.y_min = cmp.map.load_edges.front();
  h.y_max = cmp.map.load_edges.back();
  for (const auto& b : cmp.map.bins)
    h.cells.push_back({b.speed_lo, b.speed_hi, b.load_lo, b.load_hi, b.mean, b.n, b.flagged});
  put("residual_map.svg", svgHeatmap(h));
}

// history.csv: appended rows; returns all rows (for the ladder plot).
constexpr const char* kDriveHistoryHeader =
    "run,command,design,drive,data_hash,model,effects,n_params,n_rows,train_rmse_A,heldout_rmse_A,aic,bic";

// The history read from the output folder before anything is written, extended by this run and
// written to `to` (the staging folder).
std::vector<std::vector<std::string>> appendHistory(HistoryFile h, const std::string& to, const DriveDiagnosis& d,
                                                    const DriveData& data, const std::string& command) {
  h.path = to;
  const auto g = historyNumber;
  for (const ModelFit& m : d.ladder) {
    std::string eff;
    for (auto e : m.effects) {
      if (!eff.empty()) eff += "+";
      eff += std::string(drive::toString(e));
    }
    appendHistoryRow(h, {std::to_string(h.next_run), command, d.design, d.joint, data.hash, m.label, eff,
                         std::to_string(m.n_params), std::to_string(data.rows()), g(m.train_rmse),
                         g(m.heldout_rmse), g(m.aic), g(m.bic)});
  }
  writeHistory(h);
  return h.rows;
}

}  // namespace

namespace {

std::string tomlString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Line-level edit of the original design text, which keeps its comments and layout: the design
// name, one note in the assumptions, the drive's [drive.friction] table and [model].effects.
// Returns "" when the file's layout is not the simple one this expects.
std::string editDesignText(const std::string& text, const Model& original, const Model& cal, const std::string& joint,
                           const std::string& new_name, const std::string& note) {
  std::vector<std::string> lines;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) lines.push_back(l);
  auto isHeader = [&](std::size_t i) { return !trimmed(lines[i]).empty() && trimmed(lines[i])[0] == '['; };
  std::string section;  // current [table] or [[array]] name
  std::size_t drive_start = std::string::npos, friction_start = std::string::npos, friction_end = lines.size();
  std::size_t drive_end = lines.size(), name_line = std::string::npos, assumptions_close = std::string::npos;
  std::size_t model_line = std::string::npos, effects_line = std::string::npos;
  bool in_target = false, in_assumptions = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string t = trimmed(lines[i]);
    if (isHeader(i)) {
      section = t.rfind("[[", 0) == 0 ? t.substr(0, t.find("]]") + 2) : t.substr(0, t.find(']') + 1);
      if (section == "[[drive]]") {
        if (in_target && drive_end == lines.size()) drive_end = i;
        in_target = false;
      } else if (section != "[drive.friction]") {
        if (in_target && drive_end == lines.size()) drive_end = i;
        in_target = false;
      }
      if (section == "[drive.friction]" && in_target) friction_start = i;
      else if (friction_start != std::string::npos && friction_end == lines.size()) friction_end = i;
      if (section == "[model]") model_line = i;
      if (section == "[[drive]]") drive_start = i;  // candidate; confirmed by its joint line
      continue;
    }
    if (section == "[design]" && t.rfind("name", 0) == 0 && t.find('=') != std::string::npos) name_line = i;
    if (section == "[design]" && t.rfind("assumptions", 0) == 0) in_assumptions = t.find(']') == std::string::npos;
    else if (in_assumptions && t == "]") {
      assumptions_close = i;
      in_assumptions = false;
    }
    if (section == "[model]" && t.rfind("effects", 0) == 0) effects_line = i;
    if (section == "[[drive]]" && t.rfind("joint", 0) == 0) {
      const auto q1 = t.find('"'), q2 = t.rfind('"');
      if (q1 != std::string::npos && q2 > q1 && t.substr(q1 + 1, q2 - q1 - 1) == joint) {
        in_target = true;
        drive_end = lines.size();
        (void)drive_start;
      }
    }
  }
  if (name_line == std::string::npos || assumptions_close == std::string::npos) return "";
  if (model_line != std::string::npos && effects_line == std::string::npos) return "";
  const Drive* cd = nullptr;
  for (const Drive& x : cal.drives)
    if (x.joint == joint) cd = &x;
  std::vector<std::string> fr = {"[drive.friction]", "law = " + tomlString(cd->friction_law)};
  char buf[64];
  for (const auto& [k, v] : cd->friction) {
    std::snprintf(buf, sizeof buf, "%.10g", v);
    fr.push_back(k + " = " + buf);
  }
  std::string eff = "effects = [";
  for (std::size_t i = 0; i < cal.effects.size(); ++i) eff += (i ? ", " : "") + tomlString(cal.effects[i]);
  eff += "]";
  // Apply edits from the bottom up so earlier indices stay valid.
  std::vector<std::pair<std::size_t, std::vector<std::string>>> edits;  // replace [first, second) ranges
  std::vector<std::string> out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i == name_line) {
      out.push_back("name = " + tomlString(new_name));
      continue;
    }
    if (i == assumptions_close) out.push_back("  " + tomlString(note) + ",");
    if (i == effects_line) {
      out.push_back(eff);
      continue;
    }
    if (friction_start != std::string::npos && i >= friction_start && i < friction_end) {
      if (i == friction_start) {
        for (const auto& l : fr) out.push_back(l);
        out.push_back("");
      }
      continue;
    }
    if (friction_start == std::string::npos && in_target == false && i == drive_end && drive_end < lines.size()) {
      for (const auto& l : fr) out.push_back(l);
      out.push_back("");
    }
    out.push_back(lines[i]);
  }
  if (friction_start == std::string::npos && drive_end == lines.size()) {
    out.push_back("");
    for (const auto& l : fr) out.push_back(l);
  }
  if (model_line == std::string::npos) {
    out.push_back("");
    out.push_back("[model]");
    out.push_back(eff);
  }
  (void)original;
  std::string res;
  for (const auto& l : out) res += l + "\n";
  return res;
}

bool sameDrive(const Model& a, const Model& b, const std::string& joint) {
  const Drive *da = nullptr, *db = nullptr;
  for (const Drive& x : a.drives) if (x.joint == joint) da = &x;
  for (const Drive& x : b.drives) if (x.joint == joint) db = &x;
  if (!da || !db || da->friction_law != db->friction_law || da->friction.size() != db->friction.size()) return false;
  for (const auto& [k, v] : da->friction) {
    const auto it = db->friction.find(k);
    if (it == db->friction.end() || std::abs(it->second - v) > 1e-8 * (1 + std::abs(v))) return false;
  }
  return a.effects == b.effects && a.dof() == b.dof() && a.drives.size() == b.drives.size();
}

}  // namespace

std::string calibratedDesignToml(const Model& original, const Model& cal, const std::string& joint,
                                 const std::string& note) {
  const std::string name = original.name + "_calibrated";
  const std::string header = "# Calibrated copy of " + original.file + " written by `armstudy fit` (docs/calibration.md).\n";
  const std::string text = readFileOrThrow(original.file);
  std::string edited = editDesignText(text, original, cal, joint, name, note);
  if (!edited.empty()) {
    edited = header + edited;
    try {
      if (sameDrive(parseDesign(edited, name + ".toml"), cal, joint)) return edited;
    } catch (const InputError&) {
      // fall through to the re-serialised form below
    }
  }
  // Fallback for layouts the line editor does not handle: re-serialise with toml++ (comments lost).
  toml::table root;
  try {
    root = toml::parse(text, original.file);
  } catch (const toml::parse_error& e) {
    throw InputError(original.file, static_cast<int>(e.source().begin.line), "", "TOML syntax error");
  }
  if (auto* d = root["design"].as_table()) {
    d->insert_or_assign("name", name);
    toml::array as;
    if (auto* a = (*d)["assumptions"].as_array()) as = *a;
    as.push_back(note);
    d->insert_or_assign("assumptions", as);
  }
  const Drive* cd = nullptr;
  for (const Drive& x : cal.drives)
    if (x.joint == joint) cd = &x;
  ARMSTUDY_CHECK(cd != nullptr, "calibrated model has the drive");
  if (auto* drives = root["drive"].as_array())
    for (auto& n : *drives) {
      auto* t = n.as_table();
      if (!t || (*t)["joint"].value_or(std::string()) != joint) continue;
      toml::table fr;
      fr.insert("law", cd->friction_law);
      for (const auto& [k, v] : cd->friction) fr.insert(k, v);
      t->insert_or_assign("friction", fr);
    }
  toml::array eff;
  for (const auto& e : cal.effects) eff.push_back(e);
  if (!root.contains("model")) root.insert("model", toml::table{});
  root["model"].as_table()->insert_or_assign("effects", eff);
  std::ostringstream os;
  os << header << root << "\n";
  const std::string out = os.str();
  ARMSTUDY_CHECK(sameDrive(parseDesign(out, name + ".toml"), cal, joint), "calibrated design reads back");
  return out;
}

DriveReportSummary writeDriveReport(const DriveDiagnosis& d, const Model& model, const DriveData& data,
                                    const DriveReportOptions& o) {
  ARMSTUDY_CHECK(!o.out_dir.empty(), "output folder");
  DriveReportSummary sum;
  std::vector<std::string>& files = sum.files_written;
  const bool fitted = o.command == "fit";
  // Validate first (a history of another kind is an error), then write everything into a staging
  // folder and move the complete result into place (issue 13).
  const HistoryFile history = readHistory((fs::path(o.out_dir) / "history.csv").string(), kDriveHistoryHeader);
  StagedOutput stage(o.out_dir);
  const std::string dir = stage.dir();

  // residuals.csv
  {
    std::vector<std::string> h = {"line", "speed", "load_torque", "current", "predicted_as_designed",
                                  "residual_as_designed"};
    std::vector<std::vector<double>> cols(6);
    for (int i = 0; i < data.rows(); ++i) {
      cols[0].push_back(data.lines[i]);
      cols[1].push_back(data.speed[i]);
      cols[2].push_back(data.load[i]);
      cols[3].push_back(data.current[i]);
      cols[4].push_back(d.as_designed.predicted[i]);
      cols[5].push_back(d.as_designed.residual[i]);
    }
    if (fitted) {
      for (const char* n : {"predicted_final", "residual_final", "heldout_residual_final"}) h.push_back(n);
      cols.push_back(d.final_fit.predicted);
      cols.push_back(d.final_fit.residual);
      cols.push_back(d.final_fit.heldout_residual);
    }
    if (data.hasTemperature()) {
      h.push_back("temperature");
      cols.push_back(data.temperature);
    }
    writeFileAtomic((fs::path(dir) / "residuals.csv").string(), io::formatCsv(h, cols));
    files.push_back("residuals.csv");
  }
  writePlots(dir, "as_designed", d.as_designed, d.as_designed_cmp, data, d.noise_estimate, files);
  if (fitted) {
    writePlots(dir, "before", d.base, d.base_cmp, data, d.noise_estimate, files);
    if (!d.added.empty()) writePlots(dir, "after", d.final_fit, d.final_cmp, data, d.noise_estimate, files);
  }

  // History and the error ladder.
  const auto rows = appendHistory(history, (fs::path(dir) / "history.csv").string(), d, data, o.command);
  files.push_back("history.csv");
  {
    PlotSpec p;
    p.title = "error ladder (" + d.design + ", drive " + d.joint + ")";
    p.y_label = "current RMSE [A]";
    PlotSeries train{"train RMSE", {}, {}, "#1f77b4", true, true};
    PlotSeries held{"held-out RMSE", {}, {}, "#d62728", true, true};
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      p.x_categories.push_back(r[0] + ": " + r[5]);
      train.x.push_back(double(i));
      held.x.push_back(double(i));
      train.y.push_back(std::atof(r[9].c_str()));
      held.y.push_back(std::atof(r[10].c_str()));
    }
    p.series = {train, held};
    p.series.push_back({"noise estimate", {}, {}, "#888888", false, false});
    p.h_lines = {d.noise_estimate};
    p.x_label = "run: model";
    writeFileAtomic((fs::path(dir) / "error_ladder.svg").string(), svgPlot(p));
    files.push_back("error_ladder.svg");
  }

  std::string design_elsewhere;  // the calibrated copy at a path outside the output folder
  if (fitted && o.write_calibrated_design) {
    sum.calibrated_design_path = o.calibrated_design_path.empty()
                                     ? (fs::path(o.out_dir) / (model.name + "_calibrated.toml")).string()
                                     : o.calibrated_design_path;
    std::string eff;
    for (auto e : d.final_fit.effects) { eff += eff.empty() ? "" : "+"; eff += std::string(drive::toString(e)); }
    char note[512];
    std::snprintf(note, sizeof note,
                  "Drive %s friction (%s) fitted by `armstudy fit` to %s (%d rows, data %s): held-out current RMSE "
                  "%.4g A (before: %.4g A).",
                  d.joint.c_str(), eff.c_str(), data.file.c_str(), data.rows(), data.hash.c_str(), d.rmse_after,
                  d.rmse_before);
    design_elsewhere = calibratedDesignToml(model, d.calibrated, d.joint, note);
    if (o.calibrated_design_path.empty()) {  // in the output folder: staged with the rest
      writeFileAtomic((fs::path(dir) / (model.name + "_calibrated.toml")).string(), design_elsewhere);
      design_elsewhere.clear();
    }
    files.push_back(sum.calibrated_design_path);
  }

  // result.json last: its presence marks a complete run.
  json j;
  j["kind"] = "drive";
  j["command"] = o.command;
  j["design"] = {{"name", model.name}, {"file", model.file}, {"hash", model.file_hash}};
  j["drive"] = d.joint;
  j["data"] = {{"file", data.file}, {"hash", data.hash}, {"rows", data.rows()},
               {"temperature", data.hasTemperature()}};
  j["warnings"] = d.warnings;
  j["noise_estimate"] = d.noise_estimate;
  j["noise_autocorrelation"] = d.noise_rho;
  const ModelFit& fin = fitted ? d.final_fit : d.as_designed;
  const Comparison& fcmp = fitted ? d.final_cmp : d.as_designed_cmp;
  j["channels"] = {{"current", statsJson(fcmp.current, "A")},
                   {"friction_torque", statsJson(fcmp.friction_torque, "N m")}};
  j["rmse"] = {{"current", finite(fin.heldout_rmse)}, {"overall", finite(fin.heldout_rmse)}};
  j["as_designed"] = {{"model", fitJson(d.as_designed)},
                      {"channels",
                       {{"current", statsJson(d.as_designed_cmp.current, "A")},
                        {"friction_torque", statsJson(d.as_designed_cmp.friction_torque, "N m")}}},
                      {"regions", regionsJson(d.as_designed_cmp.map)}};
  j["regions"] = regionsJson(fcmp.map);
  j["bins"] = {{"speed_edges", fcmp.map.speed_edges}, {"load_edges", fcmp.map.load_edges}, {"z", fcmp.map.z},
               {"rho", fcmp.map.rho}};
  if (fitted) {
    j["refit"] = fitJson(d.base);
    j["regions_before"] = regionsJson(d.base_cmp.map);
    j["ranking"] = rankingJson(d.ranking);
    j["verdict"] = d.verdict;
    json added = json::array();
    for (auto e : d.added) added.push_back(drive::toString(e));
    j["added"] = added;
    j["rmse_before"] = finite(d.rmse_before);
    j["rmse_after"] = finite(d.rmse_after);
    j["final"] = fitJson(d.final_fit);
    json after = json::array();
    for (const auto& r : d.rankings_after) after.push_back(rankingJson(r));
    j["rankings_after"] = after;
    if (!sum.calibrated_design_path.empty()) j["calibrated_design"] = sum.calibrated_design_path;
  }
  json ladder = json::array();
  for (const auto& m : d.ladder) ladder.push_back(fitJson(m));
  j["ladder"] = ladder;
  j["files"] = files;
  sum.json = j.dump(2) + "\n";
  writeFileAtomic((fs::path(dir) / "result.json").string(), sum.json);
  stage.commit();
  if (!design_elsewhere.empty()) writeFileAtomic(sum.calibrated_design_path, design_elsewhere);
  files.push_back("result.json");
  return sum;
}

}  // namespace armstudy::calibration
