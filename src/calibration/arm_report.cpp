// Outputs of compare/fit, the one report writer of every kind (drive, tcp, trajectory):
// docs/calibration.md, "Outputs".
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "calibration/arm_calibration.hpp"
#include "calibration/history.hpp"
#include "common/errors.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"
#include "io/vtk_io.hpp"
#include "report/plot.hpp"

namespace armstudy::calibration {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

json finite(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json statsJson(const ArmProblem& P, const std::vector<ChannelStats>& s,
               const std::vector<double>& noise = {}) {
  json j = json::object();
  for (std::size_t c = 0; c < s.size(); ++c) {
    j[P.channel_names[c]] = {{"rmse", finite(s[c].rmse)},
                             {"bias", finite(s[c].bias)},
                             {"max", finite(s[c].max_abs)},
                             {"unit", P.channel_units[c]}};
    if (c < noise.size()) {  // the channel's noise estimate and the RMSE in units of it
      j[P.channel_names[c]]["noise"] = finite(noise[c]);
      j[P.channel_names[c]]["rmse_over_noise"] =
          noise[c] > 0 ? finite(s[c].rmse / noise[c]) : json(nullptr);
    }
  }
  return j;
}

json patternsJson(const std::vector<ArmPattern>& ps) {
  json a = json::array();
  for (std::size_t k = 0; k < ps.size() && k < 20; ++k) {  // the 20 strongest
    const ArmPattern& p = ps[k];
    json j = {{"channel", p.channel},
              {"variable", p.variable},
              {"unit", p.unit},
              {"kind", toString(p.kind)},
              {"statistic", finite(p.statistic)},
              {"threshold", finite(p.threshold)},
              {"significant", p.significant},
              {"explained", finite(p.explained)},
              {"description", p.description}};
    if (p.kind == PatternKind::periodic) {
      j["period"] = finite(p.period);
      j["amplitude"] = finite(p.amplitude);
    } else {
      j["peak_mean"] = finite(p.peak_mean);
      j["peak_range"] = {finite(p.peak_lo), finite(p.peak_hi)};
    }
    a.push_back(j);
  }
  return a;
}

json paramsJson(const std::vector<FittedParameter>& ps) {
  json a = json::array();
  for (const auto& p : ps)
    a.push_back({{"key", p.key},
                 {"unit", p.unit},
                 {"value", finite(p.value)},
                 {"ci_low", finite(p.ci_low)},
                 {"ci_high", finite(p.ci_high)},
                 {"at_bound", p.at_bound}});
  return a;
}

json fitJson(const ArmProblem& P, const ArmFit& f) {
  return {{"label", f.label},
          {"effects", f.effects},
          {"n_params", f.n_params},
          {"train_rmse", finite(f.train_rmse)},
          {"heldout_rmse", finite(f.heldout_rmse)},
          {"region_heldout_rmse", finite(f.region_heldout_rmse)},
          {"train_score", finite(f.train_score)},
          {"heldout_score", finite(f.heldout_score)},
          {"aic", finite(f.aic)},
          {"bic", finite(f.bic)},
          {"channels_heldout", statsJson(P, f.channel_heldout)},
          {"params", paramsJson(f.params)}};
}

json regionsJson(const ArmResidualMap& m, bool flagged_only) {
  json a = json::array();
  for (const auto& b : m.bins) {
    if (flagged_only && !b.flagged) continue;
    a.push_back({{"space", b.space},
                 {"variable", b.variable},
                 {"index", b.index},
                 {"lo", b.lo},
                 {"hi", b.hi},
                 {"n", b.n},
                 {"n_eff", b.n_eff},
                 {"mean", b.mean},
                 {"threshold", b.threshold},
                 {"flagged", b.flagged}});
  }
  return a;
}

// The unit residual figures use: millimetres for lengths (a TCP error of a few mm is invisible on
// a metre scale), else the channel's own unit.
struct PlotUnit {
  double scale = 1;  // figure value = scale * native value
  std::string name;
};
PlotUnit residualUnit(const std::string& unit) {
  if (unit == "m") return {1e3, "mm"};
  return {1, unit};
}

// One y range for channel c of every model shown (before and after on one scale), in the plotted
// unit, padded by 6 %; symmetric about zero so that a bias shows as an offset.
std::array<double, 2> residualRange(const std::vector<const ArmFit*>& fits, int c, double scale) {
  double a = 0;
  for (const ArmFit* f : fits)
    for (int i = 0; i < f->residual.rows(); ++i)
      if (std::isfinite(f->residual(i, c))) a = std::max(a, std::abs(scale * f->residual(i, c)));
  if (!(a > 0)) a = 1;
  return {-1.06 * a, 1.06 * a};
}

// plots/residual_vs_predicted_<channel>.svg: measured - predicted against the predicted value,
// one panel per model in the order given (before, then after), on one y range.
void writeResidualFigures(const std::string& dir, const ArmProblem& P,
                          const std::vector<std::pair<std::string, const ArmFit*>>& models,
                          std::vector<std::string>& files) {
  std::vector<const ArmFit*> fits;
  for (const auto& m : models) fits.push_back(m.second);
  for (int c = 0; c < P.channels(); ++c) {
    const PlotUnit u = residualUnit(P.channel_units[c]);
    const std::string& name = P.channel_names[c];
    report::PlotSpec p;
    p.title = "residual of " + name + " against its prediction";
    p.x_label = "predicted " + name + " [" + P.channel_units[c] + "]";
    p.panel_height = 200;
    const std::array<double, 2> range = residualRange(fits, c, u.scale);
    for (const auto& [title, f] : models) {
      report::PlotPanel panel;
      panel.title = title;
      panel.y_label = "measured - predicted [" + u.name + "]";
      panel.y_range = range;
      panel.lines.push_back(report::RefLine{0.0, "zero", true, report::Rgb{90, 90, 90}});
      report::PlotSeries s;
      s.label = "samples";
      s.lines = false;
      s.markers = true;
      for (int i = 0; i < P.rows(); ++i) {
        s.x.push_back(f->predicted(i, c));
        s.y.push_back(u.scale * f->residual(i, c));
      }
      panel.series.push_back(s);
      p.panels.push_back(panel);
    }
    const std::string rel = "plots/residual_vs_predicted_" + name + ".svg";
    writeFileAtomic((fs::path(dir) / rel).string(), report::plot(p).svg);
    files.push_back(rel);
  }
}

// plots/<stage>_residual_vs_<variable>.svg: one panel per channel (channels of different units
// never share an axis), each channel on the range `ranges` shares with the other stage's figure.
void writeVariablePlots(const std::string& dir, const std::string& stage, const std::string& title,
                        const ArmProblem& P, const ArmFit& f,
                        const std::vector<std::array<double, 2>>& ranges,
                        std::vector<std::string>& files) {
  for (const BinVariable& v : P.variables) {
    report::PlotSpec p;
    p.title = title + " - residual vs " + v.name;
    p.x_label = v.name + " [" + v.unit + "]";
    p.panel_height = P.channels() > 1 ? 150 : 260;
    for (int c = 0; c < P.channels(); ++c) {
      const PlotUnit u = residualUnit(P.channel_units[c]);
      report::PlotPanel panel;
      panel.title = P.channel_names[c];
      panel.y_label = "residual [" + u.name + "]";
      panel.y_range = ranges[c];
      panel.lines.push_back(report::RefLine{0.0, "zero", true, report::Rgb{90, 90, 90}});
      report::PlotSeries s;
      s.label = "measured - predicted";
      s.lines = false;
      s.markers = true;
      s.x = v.values;
      for (int i = 0; i < P.rows(); ++i) s.y.push_back(u.scale * f.residual(i, c));
      panel.series.push_back(s);
      p.panels.push_back(panel);
    }
    const std::string rel = "plots/" + stage + "_residual_vs_" + v.name + ".svg";
    writeFileAtomic((fs::path(dir) / rel).string(), report::plot(p).svg);
    files.push_back(rel);
  }
}

// The cells of the 2-D grid map (drive kind: signed speed x |load|): the mean residual per cell
// (one channel), or the largest |mean| over the channels.
std::vector<report::HeatCell> gridCells(const ArmProblem& P, const ArmResidualMap& m) {
  std::vector<report::HeatCell> cells;
  if (P.grid.size() != 2) return cells;
  for (const auto& b : m.bins) {
    if (b.space != "grid") continue;
    double v = 0;
    if (P.channels() == 1)
      v = b.mean[0];
    else
      for (double x : b.mean) v = std::max(v, std::abs(x));
    cells.push_back({b.lo[0], b.hi[0], b.lo[1], b.hi[1], v, b.flagged});
  }
  return cells;
}

// The workspace map's cells: seen from above (x-y), the largest |mean residual| over z and the
// channels.
std::vector<report::HeatCell> workspaceCells(const ArmProblem& P, const ArmResidualMap& m) {
  std::vector<report::HeatCell> out;
  if (P.workspace.empty() || m.ws_dims[0] == 0) return out;
  std::map<int, report::HeatCell> cells;
  for (const auto& b : m.bins) {
    if (b.space != "workspace") continue;
    const int key = b.index[1] * m.ws_dims[0] + b.index[0];
    auto it = cells.find(key);
    if (it == cells.end())
      it = cells.emplace(key, report::HeatCell{b.lo[0], b.hi[0], b.lo[1], b.hi[1], 0.0, false})
               .first;
    for (double v : b.mean) it->second.value = std::max(it->second.value, std::abs(v));
    it->second.flagged = it->second.flagged || b.flagged;
  }
  for (const auto& [k, c] : cells) out.push_back(c);
  return out;
}

// The largest |value| of the before and after maps' cells: the one colour scale both share, so
// that a colour means the same residual before and after the fit.
double sharedScale(const std::vector<report::HeatCell>& a, const std::vector<report::HeatCell>& b) {
  double s = 0;
  for (const auto* cells : {&a, &b})
    for (const report::HeatCell& c : *cells) s = std::max(s, std::abs(c.value));
  return s;
}

// The 2-D grid map: mean residual per cell, flagged outlined, colour 0..scale (or -scale..scale).
void writeGridMap(const std::string& dir, const std::string& stage, const std::string& title,
                  const ArmProblem& P, const ArmResidualMap& m, double scale,
                  std::vector<std::string>& files) {
  report::HeatmapSpec h;
  h.cells = gridCells(P, m);
  if (h.cells.empty()) return;
  h.title = title + " - mean residual per cell (flagged outlined)";
  h.x_label = P.grid[0].name + " [" + P.grid[0].unit + "]";
  h.y_label = P.grid[1].name + " [" + P.grid[1].unit + "]";
  h.value_label = P.channels() == 1 ? "mean residual [" + P.channel_units[0] + "]"
                                    : "max |mean residual| [" + P.fit_unit + "]";
  h.x_min = h.cells.front().x_lo, h.x_max = h.cells.front().x_hi;
  h.y_min = h.cells.front().y_lo, h.y_max = h.cells.front().y_hi;
  for (const report::HeatCell& c : h.cells) {
    h.x_min = std::min(h.x_min, c.x_lo);
    h.x_max = std::max(h.x_max, c.x_hi);
    h.y_min = std::min(h.y_min, c.y_lo);
    h.y_max = std::max(h.y_max, c.y_hi);
  }
  fs::create_directories(fs::path(dir) / "plots");
  h.diverging =
      P.channels() == 1;  // a signed mean residual; several channels: max |mean| (absolute)
  h.scale = scale;
  writeFileAtomic((fs::path(dir) / "plots" / (stage + "_residual_map.svg")).string(),
                  report::heatmap(h).svg);
  files.push_back("plots/" + stage + "_residual_map.svg");
}

void writeWorkspaceVtk(const std::string& dir, const std::string& stage, const std::string& title,
                       const ArmProblem& P, const ArmFit& f, const ArmResidualMap& m, double scale,
                       std::vector<std::string>& files) {
  if (P.workspace.empty() || m.ws_dims[0] == 0) return;
  io::ImageGrid g;
  g.dims = m.ws_dims;
  for (int a = 0; a < 3; ++a) {
    g.origin[a] = m.ws_origin[a] + 0.5 * m.ws_cell[a];  // points are the cell centres
    g.spacing[a] = m.ws_cell[a] > 0 ? m.ws_cell[a] : 1e-3;
  }
  const long np = g.points();
  io::NamedArray n{"n", io::ArrayType::Int32, 1, std::vector<double>(np, 0.0)};
  io::NamedArray fl{"flagged", io::ArrayType::UInt8, 1, std::vector<double>(np, 0.0)};
  io::NamedArray mr{"mean_residual_max_abs", io::ArrayType::Float64, 1,
                    std::vector<double>(np, 0.0)};
  io::NamedArray ratio{"mean_over_threshold_max", io::ArrayType::Float64, 1,
                       std::vector<double>(np, 0.0)};
  for (const auto& b : m.bins) {
    if (b.space != "workspace") continue;
    const long id =
        (static_cast<long>(b.index[2]) * g.dims[1] + b.index[1]) * g.dims[0] + b.index[0];
    n.values[id] = b.n;
    fl.values[id] = b.flagged;
    for (std::size_t c = 0; c < b.mean.size(); ++c) {
      mr.values[id] = std::max(mr.values[id], std::abs(b.mean[c]));
      if (b.threshold[c] > 0)
        ratio.values[id] = std::max(ratio.values[id], std::abs(b.mean[c]) / b.threshold[c]);
    }
  }
  // A cell without samples has no residual: NaN (ParaView leaves it uncoloured).
  for (long id = 0; id < np; ++id)
    if (n.values[id] == 0)
      mr.values[id] = ratio.values[id] = std::numeric_limits<double>::quiet_NaN();
  g.point_arrays = {n, fl, mr, ratio};
  g.field_data =
      io::fieldData({"position: m (cell centres)", "n: 1 (samples in the cell)", "flagged: 1",
                     "mean_residual_max_abs: the channels' units (largest |mean| over them)",
                     "mean_over_threshold_max: 1"},
                    {"flagged 0: no", "flagged 1: a channel's mean residual over its threshold",
                     "mean_residual_max_abs, mean_over_threshold_max: NaN where n = 0"});
  {  // Heatmap: the cells seen from above (x-y), the largest |mean residual| over z and channels.
    report::HeatmapSpec h;  // absolute values: a sequential scale
    h.title = title + " - workspace cells, max |mean residual| over z (flagged outlined)";
    h.x_label = "x [m]";
    h.y_label = "y [m]";
    const PlotUnit u = residualUnit(P.fit_unit);  // mm for TCP positions
    h.value_label = "|mean residual| [" + u.name + "]";
    h.x_min = m.ws_origin[0];
    h.x_max = m.ws_origin[0] + m.ws_dims[0] * m.ws_cell[0];
    h.y_min = m.ws_origin[1];
    h.y_max = m.ws_origin[1] + m.ws_dims[1] * m.ws_cell[1];
    h.cells = workspaceCells(P, m);
    for (report::HeatCell& c : h.cells) c.value *= u.scale;
    h.scale = u.scale * scale;
    fs::create_directories(fs::path(dir) / "plots");
    writeFileAtomic((fs::path(dir) / "plots" / (stage + "_workspace_map.svg")).string(),
                    report::heatmap(h).svg);
    files.push_back("plots/" + stage + "_workspace_map.svg");
  }
  io::writeVti((fs::path(dir) / (stage + "_workspace_cells.vti")).string(), g);
  files.push_back(stage + "_workspace_cells.vti");
  io::PolyDataSet poly;
  poly.points = P.workspace;
  poly.vertices = true;
  for (int c = 0; c < P.channels(); ++c) {
    io::NamedArray a{"residual_" + P.channel_names[c], io::ArrayType::Float64, 1, {}};
    for (int i = 0; i < P.rows(); ++i) a.values.push_back(f.residual(i, c));
    poly.point_arrays.push_back(a);
  }
  std::vector<std::string> units{"position: m (TCP position of each data row in W)"};
  for (int c = 0; c < P.channels(); ++c)
    units.push_back("residual_" + P.channel_names[c] + ": " + P.channel_units[c]);
  poly.field_data = io::fieldData(units);
  io::writeVtp((fs::path(dir) / (stage + "_residual_points.vtp")).string(), poly);
  files.push_back(stage + "_residual_points.vtp");
}

// The rows of this run appended to the output folder's history (read before anything is written:
// a history of another kind is an InputError), written to `to` (the staging folder).
std::vector<std::vector<std::string>> appendHistory(HistoryFile h, const std::string& to,
                                                    const ArmDiagnosis& d, const ArmProblem& P,
                                                    const std::string& command) {
  h.path = to;
  const auto g = historyNumber;
  for (const ArmFit& f : d.ladder) {
    std::string eff;
    for (const auto& e : f.effects) eff += (eff.empty() ? "" : "+") + e;
    appendHistoryRow(
        h, {std::to_string(h.next_run), command, d.kind, d.design, P.hash.empty() ? "-" : P.hash,
            f.label, eff.empty() ? "-" : eff, std::to_string(f.n_params), std::to_string(P.rows()),
            g(f.train_rmse), g(f.heldout_rmse), P.fit_unit, g(f.aic), g(f.bic)});
  }
  writeHistory(h);
  return h.rows;
}

// residuals.csv: operating variables, measured, predicted, residual (final model).
void writeResidualsCsv(const std::string& dir, const ArmProblem& P, const ArmDiagnosis& d,
                       std::vector<std::string>& files) {
  std::vector<std::string> h;
  std::vector<std::vector<double>> cols;
  for (const auto& v : P.variables) {
    h.push_back(v.name);
    cols.push_back(v.values);
  }
  for (int c = 0; c < P.channels(); ++c) {
    const std::string& n = P.channel_names[c];
    h.insert(h.end(), {"measured_" + n, "predicted_" + n, "residual_" + n});
    std::vector<double> m, p, r;
    for (int i = 0; i < P.rows(); ++i) {
      m.push_back(P.measured(i, c));
      p.push_back(d.final_fit.predicted(i, c));
      r.push_back(d.final_fit.residual(i, c));
    }
    cols.push_back(m);
    cols.push_back(p);
    cols.push_back(r);
  }
  writeFileAtomic((fs::path(dir) / "residuals.csv").string(), io::formatCsv(h, cols));
  files.push_back("residuals.csv");
}

// error_ladder.svg: training and held-out RMSE of every history row, with the noise estimate.
void writeErrorLadder(const std::string& dir, const ArmDiagnosis& d, const ArmProblem& P,
                      const std::vector<std::vector<std::string>>& rows,
                      std::vector<std::string>& files) {
  report::PlotSpec p;
  p.title = "error ladder (" + d.design + ", " + d.kind + ")";
  report::PlotPanel panel;
  panel.y_label = "RMSE [" + P.fit_unit + "]";
  report::PlotSeries tr, ho;
  tr.label = "training";
  ho.label = "held-out";
  tr.markers = ho.markers = true;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    p.x_categories.push_back(rows[i][0] + ":" + rows[i][5]);
    tr.x.push_back(static_cast<double>(i));
    ho.x.push_back(static_cast<double>(i));
    tr.y.push_back(std::atof(rows[i][9].c_str()));
    ho.y.push_back(std::atof(rows[i][10].c_str()));
  }
  panel.series = {tr, ho};
  panel.lines.push_back(
      report::RefLine{d.noise_estimate, "noise estimate", true, report::Rgb{90, 90, 90}});
  p.panels.push_back(panel);
  writeFileAtomic((fs::path(dir) / "error_ladder.svg").string(), report::plot(p).svg);
  files.push_back("error_ladder.svg");
}

// The ranking of result.json: each candidate effect, its fit and its verdict.
json rankingJson(const ArmDiagnosis& d, const ArmProblem& P) {
  json rk = json::array();
  for (const auto& c : d.ranking)
    rk.push_back({{"effect", c.name},
                  {"catalogue", P.catalogue[c.effect].effect},
                  {"pattern", P.catalogue[c.effect].pattern},
                  {"status", c.status},
                  {"heldout_rmse", c.status == "ok" ? finite(c.fit.heldout_rmse) : json(nullptr)},
                  {"region_heldout_rmse",
                   c.status == "ok" ? finite(c.fit.region_heldout_rmse) : json(nullptr)},
                  {"heldout_score", c.status == "ok" ? finite(c.fit.heldout_score) : json(nullptr)},
                  {"improvement", finite(c.improvement)},
                  {"t_statistic", finite(c.t_statistic)},
                  {"significant", c.significant},
                  {"params", paramsJson(c.fit.params)},
                  {"warnings", c.warnings},
                  {"indistinguishable_from", c.indistinguishable}});
  return rk;
}

// result.json: data, errors before and after, noise, ranking, regions, ladder and files.
// `path` as written from `folder` (so that result.json does not depend on where the output
// folder lies): relative when it lies inside the folder, else absolute.
std::string pathFromFolder(const std::string& path, const std::string& folder) {
  if (path.empty()) return path;  // no calibrated copy
  const fs::path rel = fs::absolute(path).lexically_normal().lexically_relative(
      fs::absolute(folder).lexically_normal());
  if (rel.empty() || *rel.begin() == "..") return fs::absolute(path).lexically_normal().string();
  return rel.string();
}

json resultJson(const ArmDiagnosis& d, const ArmProblem& P, const ArmReportOptions& o,
                const std::string& calibrated_design_path, const std::vector<std::string>& files) {
  json j;
  j["kind"] = d.kind;
  j["command"] = o.command;
  j["design"] = d.design;
  j["data"] = {
      {"file", P.file}, {"hash", P.hash}, {"rows", P.rows()}, {"channels", P.channel_names}};
  j["unit"] = P.fit_unit;
  j["warnings"] = d.warnings;
  j["rmse"] = {{"overall", finite(d.final_fit.heldout_rmse)},
               {"train", finite(d.final_fit.train_rmse)},
               {"region_heldout", finite(d.final_fit.region_heldout_rmse)},
               {"normalized", finite(d.final_fit.heldout_score)},
               {"normalized_train", finite(d.final_fit.train_score)},
               {"channels", statsJson(P, d.final_fit.channel_heldout, d.channel_noise)}};
  j["as_designed"] = {{"rmse", finite(d.as_designed.train_rmse)},
                      {"normalized", finite(d.as_designed.train_score)},
                      {"channels", statsJson(P, d.as_designed.channel_train, d.channel_noise)}};
  j["noise_estimate"] = finite(d.noise_estimate);
  j["channel_noise"] = d.channel_noise;
  j["noise_autocorrelation"] = finite(d.noise_rho);
  j["ranking"] = rankingJson(d, P);
  j["verdict"] =
      o.command == "compare" ? "compare only (run fit to rank candidate effects)" : d.verdict;
  j["regions"] = regionsJson(d.final_map, true);
  j["regions_before"] = regionsJson(d.as_designed_map, true);
  j["flagged_before"] = d.as_designed_map.flagged();
  j["flagged_after"] = d.final_map.flagged();
  if (o.command == "fit") {
    j["unexplained_found"] = d.unexplained_found;
    j["patterns"] = patternsJson(d.patterns);
    json rem = json::array();
    for (const ArmRemainder& r : d.remainders)
      rem.push_back({{"channel", r.channel},
                     {"variable", r.variable},
                     {"rms", r.rms},
                     {"unit", r.unit},
                     {"share_final", r.share_final},
                     {"share_design", r.share_design},
                     {"text", r.text()}});
    j["remainders"] = rem;
  }
  j["channel_resolution"] = d.channel_resolution;
  json ladder = json::array();
  for (const auto& f : d.ladder) ladder.push_back(fitJson(P, f));
  j["ladder"] = ladder;
  j["added"] = d.added;
  j["final_params"] = paramsJson(d.final_fit.params);
  if (o.command == "fit") {
    j["rmse_before"] = finite(d.rmse_before);
    j["rmse_after"] = finite(d.rmse_after);
    j["calibrated_design"] = pathFromFolder(calibrated_design_path, o.out_dir);
  }
  j["files"] = files;
  return j;
}

}  // namespace

std::string armModelTitle(ShownDesign shown, bool after, const ArmDiagnosis& d) {
  if (after) {
    // Up to two added effects by name; more as a count (the error ladder names each), so that a
    // figure's title keeps to two lines.
    std::string added;
    for (const auto& a : d.added) added += (added.empty() ? "+" : ", +") + a;
    if (d.added.size() > 2) added = "+" + std::to_string(d.added.size()) + " effects";
    return "after: calibrated" + (added.empty() ? std::string() : " (" + added + ")");
  }
  return shown == ShownDesign::calibrated_copy ? "calibrated design (check run)"
                                               : "before: as designed";
}

// Writes plots, maps, residuals, history, the error ladder and result.json into a staging folder,
// then moves the complete result into place.
ArmReportSummary writeArmReport(const ArmDiagnosis& d, const ArmProblem& P,
                                const ArmReportOptions& o,
                                const std::string& calibrated_design_path) {
  ArmReportSummary s;
  // Validate first (the history in the folder must be of this kind), then write every file into a
  // staging folder and move the complete result into place.
  StagedOutput stage(o.out_dir,
                     o.lock);  // locks the folder first: the history read is the one appended to
  const HistoryFile history = readHistory((fs::path(o.out_dir) / "history.csv").string(), P.kind);
  const std::string dir = stage.dir();
  const bool after = o.command == "fit" && !d.added.empty();
  // Before and after share each map's colour scale.
  const std::vector<report::HeatCell> none;
  const double ws_scale = sharedScale(workspaceCells(P, d.as_designed_map),
                                      after ? workspaceCells(P, d.final_map) : none);
  const double grid_scale =
      sharedScale(gridCells(P, d.as_designed_map), after ? gridCells(P, d.final_map) : none);
  // The figures' titles name the model they show, before then after.
  const std::string before_title = armModelTitle(o.shown, false, d);
  const std::string after_title = armModelTitle(o.shown, true, d);
  std::vector<std::pair<std::string, const ArmFit*>> models{{before_title, &d.as_designed}};
  if (after) models.emplace_back(after_title, &d.final_fit);
  fs::create_directories(fs::path(dir) / "plots");
  writeResidualFigures(dir, P, models, s.files_written);
  std::vector<std::array<double, 2>> ranges;  // per channel, shared by before and after
  for (int c = 0; c < P.channels(); ++c) {
    std::vector<const ArmFit*> fits;
    for (const auto& m : models) fits.push_back(m.second);
    ranges.push_back(residualRange(fits, c, residualUnit(P.channel_units[c]).scale));
  }
  writeVariablePlots(dir, "before", before_title, P, d.as_designed, ranges, s.files_written);
  writeWorkspaceVtk(dir, "before", before_title, P, d.as_designed, d.as_designed_map, ws_scale,
                    s.files_written);
  writeGridMap(dir, "before", before_title, P, d.as_designed_map, grid_scale, s.files_written);
  if (after) {
    writeVariablePlots(dir, "after", after_title, P, d.final_fit, ranges, s.files_written);
    writeWorkspaceVtk(dir, "after", after_title, P, d.final_fit, d.final_map, ws_scale,
                      s.files_written);
    writeGridMap(dir, "after", after_title, P, d.final_map, grid_scale, s.files_written);
  }
  writeResidualsCsv(dir, P, d, s.files_written);
  const auto rows =
      appendHistory(history, (fs::path(dir) / "history.csv").string(), d, P, o.command);
  s.files_written.push_back("history.csv");
  writeErrorLadder(dir, d, P, rows, s.files_written);
  s.json = resultJson(d, P, o, calibrated_design_path, s.files_written).dump(2);
  for (const auto& [name, text] : o.extra_files)
    writeFileAtomic((fs::path(dir) / name).string(), text);
  writeFileAtomic((fs::path(dir) / "result.json").string(), s.json + "\n");
  stage.commit();
  return s;
}

}  // namespace armstudy::calibration
