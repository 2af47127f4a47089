// The [explore] stage run: search, Pareto front, report, front designs (explore.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "common/format.hpp"
#include "io/urdf_io.hpp"
#include "report/document.hpp"
#include "stages/explore/explore_internal.hpp"
#include "stages/explore/explore_plots.hpp"

namespace armstudy::explore {

namespace {

namespace fs = std::filesystem;

// Numbers in the report: 4 significant digits.

std::string goalText(Goal g) {
  return g == Goal::Maximise ? "max" : g == Goal::Minimise ? "min" : "constraint";
}

// Larger is better for objective k.
double oriented(const Objective& ob, double v) { return ob.goal == Goal::Minimise ? -v : v; }

// Two metric values closer than this are the same value (rounding of the metrics' arithmetic).
constexpr double kSameValue = 1e-12;

}  // namespace

std::string fileSafeName(const std::string& candidate) {
  std::string s;
  for (char ch : candidate) s += ch == '+' ? "__" : ch == '=' ? "_" : std::string(1, ch);
  return s;
}

namespace {

// The search's outcome that every output reads: candidates, the sorted front, the base design.
struct Outcome {
  const ExploreOptions& o;
  const std::vector<Candidate>& c;
  std::vector<std::size_t> front;  // best first by the first objective with a goal, then by name
  std::size_t base_index = 0;
  std::vector<std::size_t> goals;  // the objectives with a goal
  bool base_on_front = false;
};

// The Pareto front of the candidates, best first by the first objective with a goal, then by name
// (stable).
std::vector<std::size_t> sortedFront(const ExploreOptions& o, const std::vector<Candidate>& c) {
  std::vector<std::size_t> front = paretoFront(c, o.objectives);
  std::size_t k0 = 0;
  while (o.objectives[k0].goal == Goal::None) ++k0;
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
    const double va = oriented(o.objectives[k0], c[a].values[k0]),
                 vb = oriented(o.objectives[k0], c[b].values[k0]);
    return va != vb ? va > vb : c[a].name < c[b].name;
  });
  return front;
}

// The indices of the objectives with a goal (the others are constraints only).
std::vector<std::size_t> goalObjectives(const ExploreOptions& o) {
  std::vector<std::size_t> goals;
  for (std::size_t k = 0; k < o.objectives.size(); ++k)
    if (o.objectives[k].goal != Goal::None) goals.push_back(k);
  return goals;
}

// candidates.csv: every evaluated candidate with its parameters, values and front/base flags.
std::string candidatesCsv(const Outcome& r) {
  const ExploreOptions& o = r.o;
  const std::vector<Candidate>& c = r.c;
  std::ostringstream s;
  s << "name";
  for (const Parameter& p : o.parameters) s << "," << p.key;
  for (const Objective& ob : o.objectives) s << "," << ob.label;
  s << ",feasible,on_front,is_base\n";
  for (std::size_t i = 0; i < c.size(); ++i) {
    s << c[i].name;
    for (std::size_t p = 0; p < o.parameters.size(); ++p)
      s << "," << (c[i].params.empty() ? "" : formatShortest(c[i].params[p]));
    for (double v : c[i].values) s << "," << formatShortest(v);
    s << "," << (c[i].feasible ? 1 : 0) << ","
      << (std::count(r.front.begin(), r.front.end(), i) ? 1 : 0) << ","
      << (i == r.base_index ? 1 : 0) << "\n";
  }
  return s.str();
}

// The front designs whose stage outputs are written: the first front_designs of the front, less
// the base design (its own outputs are the study's).
std::vector<std::size_t> shownFront(const Outcome& r) {
  std::vector<std::size_t> shown;
  for (std::size_t f = 0; f < r.front.size() && static_cast<int>(f) < r.o.front_designs; ++f)
    if (r.front[f] != r.base_index) shown.push_back(r.front[f]);
  return shown;
}

// The tops of the colour scales over the shown front designs (each run alone into a scratch
// folder, removed after), so that their maps share one scale for real.
std::map<std::string, double> frontScaleTops(const Evaluator& ev, const Outcome& r,
                                             const std::string& scratch) {
  std::map<std::string, double> tops;
  for (std::size_t i : shownFront(r)) {
    const Model m = deriveVariant(r.o.base, r.c[i].overrides, r.o.file, r.o.line);
    for (const auto& [scale, top] : ev.runStages(m, r.c[i].overrides, scratch).scale_tops)
      tops[scale] = std::max(tops[scale], top);
    std::error_code ec;
    fs::remove_all(scratch, ec);
  }
  return tops;
}

// Writes the first front_designs front designs (the base design excepted): design file plus the
// stages' own outputs (maps on the colour scales they share), from the checkpointed units; returns
// their file-safe names; their stages' report documents go to `reports`.
std::vector<std::string> writeFrontDesigns(const StageContext& ctx, const Evaluator& ev,
                                           const Outcome& r, Writer& out,
                                           std::vector<report::ReportFile>& reports) {
  const ExploreOptions& o = r.o;
  std::vector<std::string> written;
  const std::map<std::string, double> tops = frontScaleTops(ev, r, out.path("explore/.scales"));
  for (std::size_t i : shownFront(r)) {
    const Candidate& cand = r.c[i];
    const Model m = deriveVariant(o.base, cand.overrides, o.file, o.line);
    const std::string safe = fileSafeName(cand.name);
    const std::string rel = "explore/front/" + safe;
    Model file_model =
        m;  // as a design file: a valid design name, the variant named in the description
    file_model.name = safe;
    file_model.description = "Variant " + cand.name + " of " + o.base.name +
                             " (Pareto front of study " + ctx.study.name + "). " + m.description;
    out.text(rel + "/" + safe + ".toml", designToToml(file_model));
    const StageResult sr = ev.runStages(m, cand.overrides, out.path(rel), tops);
    for (const std::string& file : sr.files) out.add(rel + "/" + file);
    for (const report::ReportFile& f : sr.reports) reports.push_back({rel + "/" + f.path, f.doc});
    written.push_back(safe);
  }
  return written;
}

// The report's title, the search status and the parameter and objective tables.
report::Document introDocument(const StageContext& ctx, const Evaluator& ev, const Outcome& r) {
  const ExploreOptions& o = r.o;
  std::string stages;
  for (std::size_t s = 0; s < o.stages.size(); ++s)
    stages += (s ? ", " : "") + std::string("`") + o.stages[s] + "`";
  report::Document doc;
  doc.heading(1, "Design-space exploration: study `" + ctx.study.name + "`")
      .paragraph("Candidates are variants of `" + o.base.name +
                 "` (docs/exploration.md); each is evaluated by the stages " + stages +
                 " run on it alone.")
      .paragraph("Search: " + ev.status() + ". Evaluated: " + std::to_string(r.c.size()) +
                 " candidate(s) including the base design; " + std::to_string(r.front.size()) +
                 " on the Pareto front.");
  std::vector<std::vector<std::string>> rows;
  for (const Parameter& p : o.parameters)
    rows.push_back({p.label, "`" + p.key + "`", formatG(p.lo, 4), formatG(p.hi, 4),
                    p.step > 0         ? formatG(p.step, 4)
                    : p.values.empty() ? "continuous"
                                       : std::to_string(p.values.size()) + " values"});
  doc.heading(2, "Parameters (SI)")
      .table({"parameter", "design entry", ">from", ">to", ">step"}, std::move(rows));
  rows.clear();
  for (const Objective& ob : o.objectives)
    rows.push_back({ob.label, "`" + ob.metric + "`", goalText(ob.goal),
                    ob.min > -1e299 ? formatG(ob.min, 4) : "",
                    ob.max < 1e299 ? formatG(ob.max, 4) : ""});
  doc.heading(2, "Objectives and constraints")
      .table({"label", "metric", "goal", ">min", ">max"}, std::move(rows));
  return doc;
}

// The header of the candidate tables: design, parameters, objectives.
std::vector<std::string> candidateHeader(const ExploreOptions& o) {
  std::vector<std::string> header{"design"};
  for (const Parameter& p : o.parameters) header.push_back(">" + parameterAxisLabel(o, p));
  for (const Objective& ob : o.objectives) header.push_back(">" + objectiveAxisLabel(ob));
  return header;
}

// Candidate i as a table row: name, parameter values ("(base)" for the base design), values.
std::vector<std::string> candidateRow(const Outcome& r, std::size_t i) {
  const std::vector<Candidate>& c = r.c;
  std::vector<std::string> row{c[i].name + (i == r.base_index ? " (base design)" : "")};
  for (std::size_t p = 0; p < r.o.parameters.size(); ++p)
    row.push_back(c[i].params.empty() ? "(base)" : formatG(c[i].params[p], 4));
  for (double v : c[i].values) row.push_back(formatG(v, 4));
  return row;
}

// The front designs that dominate the base design: at least as good in every objective with a
// goal and better in one.
std::vector<std::string> dominatingBase(const Outcome& r) {
  std::vector<std::string> by;
  for (std::size_t i : r.front) {
    bool dom = true, strict = false;
    for (std::size_t k : r.goals) {
      const double a = oriented(r.o.objectives[k], r.c[i].values[k]),
                   b = oriented(r.o.objectives[k], r.c[r.base_index].values[k]);
      dom &= a >= b;
      strict |= a > b;
    }
    if (dom && strict) by.push_back("`" + r.c[i].name + "`");
  }
  return by;
}

// What the study resolves in objective k (Objective::resolution): the given value, else for a
// share ("..._fraction") the smallest difference between two candidates' values (one count), else
// 0 (only equal values are level).
double resolution(const Outcome& r, std::size_t k) {
  const Objective& ob = r.o.objectives[k];
  if (ob.resolution > 0) return ob.resolution;
  const std::string tail = "_fraction";
  if (ob.metric.size() < tail.size() ||
      ob.metric.compare(ob.metric.size() - tail.size(), tail.size(), tail) != 0)
    return 0;
  std::vector<double> v;
  for (const Candidate& c : r.c)
    if (std::isfinite(c.values[k])) v.push_back(c.values[k]);
  std::sort(v.begin(), v.end());
  double step = 0;
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i] - v[i - 1] > kSameValue && (step == 0 || v[i] - v[i - 1] < step))
      step = v[i] - v[i - 1];
  return step;
}

// One recommended front design per trade-off: for each objective with a goal, the front design
// best in it (ties: the better balanced one), with the other front designs within the
// objective's resolution of it (level: no winner); then the balanced one, whose largest shortfall
// from the front's best over the objectives, each scaled by the front's spread, is least.
struct Recommendation {
  std::string trade_off;  // "best stem map coverage", "balanced"
  std::size_t candidate = 0;
  std::vector<std::size_t> level;  // front designs as good within the resolution
  double resolution = 0;
};
std::vector<Recommendation> recommendations(const Outcome& r) {
  std::vector<Recommendation> out;
  if (r.front.empty()) return out;
  const auto value = [&](std::size_t i, std::size_t k) {
    return oriented(r.o.objectives[k], r.c[i].values[k]);
  };
  std::vector<double> best(r.o.objectives.size(), -HUGE_VAL), worst(best.size(), HUGE_VAL);
  for (std::size_t k : r.goals)
    for (std::size_t i : r.front) {
      best[k] = std::max(best[k], value(i, k));
      worst[k] = std::min(worst[k], value(i, k));
    }
  const auto shortfall = [&](std::size_t i) {  // largest scaled distance from the front's best
    double s = 0;
    for (std::size_t k : r.goals)
      if (best[k] > worst[k]) s = std::max(s, (best[k] - value(i, k)) / (best[k] - worst[k]));
    return s;
  };
  for (std::size_t k : r.goals) {
    std::size_t pick = r.front[0];
    for (std::size_t i : r.front)
      if (value(i, k) > value(pick, k) ||
          (value(i, k) == value(pick, k) && shortfall(i) < shortfall(pick)))
        pick = i;
    const std::string& label = r.o.objectives[k].label;  // without a unit: "best link length"
    Recommendation rec{"best " + label.substr(0, label.find(" [")), pick, {}, resolution(r, k)};
    for (std::size_t i : r.front)
      if (i != pick && value(pick, k) - value(i, k) <= rec.resolution + kSameValue)
        rec.level.push_back(i);
    out.push_back(std::move(rec));
  }
  std::size_t balanced = r.front[0];
  for (std::size_t i : r.front)
    if (shortfall(i) < shortfall(balanced)) balanced = i;
  out.push_back({"balanced", balanced, {}, 0});
  return out;
}

// A recommendation's level designs in words ("" when it has none): "level with 2 other front
// designs within the resolution 0.0017: `a`, `b`".
std::string levelText(const Outcome& r, const Recommendation& rec) {
  if (rec.level.empty()) return "";
  std::string s = "level with " + std::to_string(rec.level.size()) + " other front design" +
                  (rec.level.size() > 1 ? "s" : "") +
                  (rec.resolution > 0 ? " within the resolution " + formatG(rec.resolution, 4)
                                      : " of the same value") +
                  ": ";
  for (std::size_t j = 0; j < rec.level.size() && j < 3; ++j)
    s += (j ? ", `" : "`") + r.c[rec.level[j]].name + "`";
  return s + (rec.level.size() > 3 ? ", ..." : "");
}

// A candidate's objective values in words: "stem map coverage 0.8, fruits feasible 0.625, ...".
std::string valuesText(const Outcome& r, std::size_t i) {
  std::string s;
  for (std::size_t k = 0; k < r.o.objectives.size(); ++k)
    s += (k ? ", " : "") + r.o.objectives[k].label + " " + formatG(r.c[i].values[k], 4);
  return s;
}

// The stage's answer (StageResult::answer): how many candidates, the front's size, whether the base
// design is dominated (and by how many) with its values, and one recommended front design per
// trade-off with all its objective values.
std::string exploreAnswer(const Outcome& r) {
  long feasible = 0;
  for (const Candidate& x : r.c) feasible += x.feasible;
  std::string a = std::to_string(r.front.size()) + " of the " + std::to_string(r.c.size()) +
                  " candidates (" + std::to_string(feasible) +
                  " feasible) are on the Pareto front; the base design (" +
                  valuesText(r, r.base_index) + ") is ";
  if (r.base_on_front)
    a += "on it";
  else {
    const std::vector<std::string> by = dominatingBase(r);
    a += "dominated by " + std::to_string(by.size()) + " of them" +
         (by.empty() ? "" : " (e.g. " + by[0] + ")");
  }
  for (const Recommendation& rec : recommendations(r)) {
    const std::string level = levelText(r, rec);
    a += "; " + rec.trade_off + ": `" + r.c[rec.candidate].name + "` (" +
         valuesText(r, rec.candidate) + ")" + (level.empty() ? "" : ", " + level);
  }
  return a + ".";
}

// The base design against the front: its row, whether it is dominated (and by whom).
report::Document baseDocument(const Outcome& r, const std::vector<std::string>& header) {
  report::Document doc;
  doc.heading(2, "The base design relative to the front")
      .table(header, {candidateRow(r, r.base_index)});
  if (!r.c[r.base_index].feasible) doc.paragraph("The base design breaks a constraint.");
  if (r.base_on_front)
    return doc.paragraph(
        "The base design is on the front: no candidate is at least as good in every objective and "
        "better in one.");
  const std::vector<std::string> by = dominatingBase(r);
  std::string text =
      "The base design is dominated by " + std::to_string(by.size()) + " front design(s)";
  if (!by.empty()) {
    text += ": ";
    for (std::size_t k = 0; k < by.size() && k < 5; ++k) text += (k ? ", " : "") + by[k];
    if (by.size() > 5) text += ", ...";
  }
  return doc.paragraph(text + ".");
}

// The recommended front designs, each with all its values.
report::Document recommendedDocument(const Outcome& r, const std::vector<std::string>& header) {
  std::vector<std::string> rec_header = header;
  rec_header.insert(rec_header.begin(), "trade-off");
  std::vector<std::vector<std::string>> rows;
  for (const Recommendation& rec : recommendations(r)) {
    rows.push_back(candidateRow(r, rec.candidate));
    const std::string level = levelText(r, rec);
    rows.back().insert(rows.back().begin(),
                       rec.trade_off + (level.empty() ? "" : " (" + level + ")"));
  }
  return report::Document()
      .heading(2, "Recommended designs")
      .paragraph(
          "One front design per trade-off, each with all its values: the best in each objective, "
          "and the balanced one (the least largest shortfall from the front's best, each "
          "objective scaled by the front's spread). A best design with others within the "
          "objective's resolution (one cell or fruit of a share, or the study's `resolution`) is "
          "level with them, not a winner.")
      .table(std::move(rec_header), std::move(rows));
}

// The adapted geometry of the front designs and the list of files written.
report::Document geometryAndFilesDocument(const Outcome& r,
                                          const std::vector<std::string>& written) {
  report::Document doc;
  doc.heading(2, "Geometry that follows")
      .paragraph(
          "What deriving the front designs adapted (docs/exploration.md, \"Geometry that "
          "follows\"):");
  std::vector<report::ListItem> adapted;
  for (std::size_t i : r.front)
    if (!r.c[i].adapted.empty()) adapted.push_back({"`" + r.c[i].name + "`:", r.c[i].adapted});
  if (!adapted.empty()) doc.nestedList(std::move(adapted));
  std::vector<std::string> files{"`candidates.csv`: every evaluated candidate"};
  if (r.goals.size() >= 2)
    files.push_back(
        "`front_scatter.svg`: the first two objectives, front highlighted, base design marked");
  files.push_back(
      "`parallel.svg`: parallel coordinates of parameters and objectives (each objective turned "
      "so that better is up)");
  for (const std::string& n : written)
    files.push_back("`front/" + n + "/`: design file and the stages' outputs");
  return doc.heading(2, "Files").list(std::move(files));
}

// explore.md: intro and tables, the front, the base design against it, the recommended designs,
// geometry and files.
report::Document exploreDocument(const StageContext& ctx, const Evaluator& ev, const Outcome& r,
                                 const std::vector<std::string>& written) {
  const std::vector<std::string> header = candidateHeader(r.o);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i : r.front) rows.push_back(candidateRow(r, i));
  return introDocument(ctx, ev, r)
      .heading(2, "Pareto front (non-dominated feasible candidates)")
      .table(header, std::move(rows))
      .append(baseDocument(r, header))
      .append(recommendedDocument(r, header))
      .append(geometryAndFilesDocument(r, written));
}

// The exploration's metrics: evaluations, front size, whether the base is on it, front values.
void addExploreMetrics(const Outcome& r, StudyMetrics& M) {
  M.scalars["explore/evaluations"] = static_cast<double>(r.c.size());
  M.scalars["explore/front_size"] = static_cast<double>(r.front.size());
  M.scalars["explore/base_on_front"] = r.base_on_front ? 1.0 : 0.0;
  for (std::size_t f = 0; f < r.front.size(); ++f)
    for (std::size_t k = 0; k < r.o.objectives.size(); ++k)
      M.scalars["explore/front/" + r.c[r.front[f]].name + "/" + std::to_string(k)] =
          r.c[r.front[f]].values[k];
}

}  // namespace

// Evaluates the base design and runs the search, then writes candidates.csv, the plots, the front
// designs and explore.md.
StageResult runExploreStage(const StageContext& ctx, const ExploreOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult res;
  Writer out(ctx.output_dir);
  Evaluator ev(ctx, o);
  const std::size_t base_index = ev.evaluate({{}}, true)[0];
  if (o.method == Method::Grid)
    ev.searchGrid();
  else
    ev.searchOptimise();
  const std::vector<Candidate>& c = ev.candidates();
  std::vector<std::size_t> front = sortedFront(o, c);
  const bool base_on_front = std::find(front.begin(), front.end(), base_index) != front.end();
  const Outcome r{o, c, std::move(front), base_index, goalObjectives(o), base_on_front};
  out.text("explore/candidates.csv", candidatesCsv(r));
  if (r.goals.size() >= 2)
    out.text("explore/front_scatter.svg",
             frontScatterFigure(r.c, r.front, base_index, o, r.goals[0], r.goals[1]).svg);
  out.text("explore/parallel.svg", parallelFigure(r.c, r.front, base_index, o).svg);
  std::vector<report::ReportFile> front_reports;
  const std::vector<std::string> written = writeFrontDesigns(ctx, ev, r, out, front_reports);
  out.report("explore/explore.md", exploreDocument(ctx, ev, r, written));
  addExploreMetrics(r, res.metrics);
  res.answer.push_back(exploreAnswer(r));
  if (!c[base_index].feasible) res.warnings.push_back("The base design breaks a constraint.");
  res.files = out.files();
  res.reports = out.reports();
  res.reports.insert(res.reports.end(), front_reports.begin(), front_reports.end());
  res.units_resumed = ev.unitsResumed();
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace armstudy::explore
