#include "stages/harvest/harvest_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "report/markdown.hpp"
#include "report/plot.hpp"
#include "stages/harvest/harvest_report.hpp"
#include "stages/harvest/harvest_units.hpp"
#include "study/writer.hpp"

namespace armstudy::harvest {

using nlohmann::ordered_json;

namespace {

// Fruit counts of one design: evaluated, feasible with and without friction, per-fruit flags.
struct FruitCounts {
  int evaluated = 0, feasible = 0, feasible_nf = 0;
  std::vector<std::uint8_t> flags;  // evaluated and feasible with friction, per fruit
};

// Whether the stage runs for this design (an empty design list selects every design).
bool selected(const HarvestOptions& options, const Model& model) {
  return options.designs.empty() || std::find(options.designs.begin(), options.designs.end(),
                                              model.name) != options.designs.end();
}

// The report's title and opening paragraph: the row, the planner, the tracking and the dynamics.
report::Document reportIntro(const StageContext& ctx, const HarvestOptions& options,
                             const GreenhouseRow& row) {
  std::ostringstream md;
  md << "Approaches to a greenhouse row sampled from thesis Table 2.2 (seed " << options.row.seed
     << ", " << row.fruits.size() << " fruits on " << row.stems_xy.size()
     << " stems), planned with the heuristic planner of section 5.3.2 (r_e = "
     << report::fixed(options.approach.entry_radius_m, 3) << " m, s_a = " << options.approach.s_a
     << ", s_e = " << options.approach.s_e << ", T = " << options.approach.duration_s
     << " s), tracked with the null-space IK (joint limits weight " << options.w_joint_limits
     << ", manipulability weight " << options.w_manipulability << ") at "
     << report::fixed(options.rate_Hz, 0)
     << " Hz, inverse dynamics and drive chain per joint (docs/dynamics.md). Margins are "
        "(limit - value) / limit; n/a = limit not given in the design.";
  return report::Document()
      .heading(1, "Harvest torque study: " + ctx.study.name)
      .paragraph(md.str());
}

// summary.json's study-wide fields (study, row, approach, rate) with an empty design list.
ordered_json summaryHead(const StageContext& ctx, const HarvestOptions& options,
                         const GreenhouseRow& row) {
  ordered_json js;
  js["study"] = ctx.study.name;
  js["row"] = {{"seed", options.row.seed},
               {"stems", row.stems_xy.size()},
               {"fruits", row.fruits.size()},
               {"row_to_row_m", row.row_to_row_m}};
  js["approach"] = {{"entry_radius_m", options.approach.entry_radius_m},
                    {"s_a", options.approach.s_a},
                    {"s_e", options.approach.s_e},
                    {"duration_s", options.approach.duration_s}};
  js["rate_Hz"] = options.rate_Hz;
  js["designs"] = ordered_json::array();
  return js;
}

// Counts the evaluated fruits of a design and those feasible with and without friction.
FruitCounts countFruits(const DesignResult& d) {
  FruitCounts c;
  for (const FruitResult& f : d.fruits) {
    c.flags.push_back(f.evaluated() && f.with_friction.feasible ? 1 : 0);
    if (!f.evaluated()) continue;
    ++c.evaluated;
    c.feasible += f.with_friction.feasible;
    c.feasible_nf += f.without_friction.feasible;
  }
  return c;
}

// Adds a design's feasible fractions, its peak current ratio and per-joint drive peaks to M.
void addDesignMetrics(const Model& model, const DesignResult& d, const FruitCounts& c,
                      const std::vector<JointAggregate>& agg, StudyMetrics& M) {
  const int n = model.dof();
  const std::string mprefix = "harvest/" + model.name + "/";
  const double nfr = std::max<double>(1, static_cast<double>(d.fruits.size()));
  M.scalars[mprefix + "evaluated_fraction"] = c.evaluated / nfr;
  M.scalars[mprefix + "feasible_fraction"] = c.feasible / nfr;
  M.scalars[mprefix + "feasible_fraction_no_friction"] = c.feasible_nf / nfr;
  M.flags[mprefix + "fruit_feasible"] = c.flags;
  // The drives' current margin in one number (an exploration objective without a holding grid):
  // the largest peak motor current over the approaches relative to its drive's peak limit, over
  // the joints whose drive gives one (margin = 1 - ratio; > 1: some approach needs more current).
  double current_ratio = 0;
  bool current_checked = false;
  for (int i = 0; i < n; ++i)
    if (agg[i].has_drive && agg[i].worst[0].checked && agg[i].worst[0].limit > 0) {
      current_checked = true;
      current_ratio = std::max(current_ratio, agg[i].worst[0].value / agg[i].worst[0].limit);
    }
  if (current_checked) M.scalars[mprefix + "peak_current_ratio"] = current_ratio;
  for (int i = 0; i < n; ++i) {
    if (!agg[i].has_drive) continue;
    const std::string jp = mprefix + model.joints[i].name + "/";
    M.scalars[jp + "peak_current_A"] = agg[i].worst[0].value;
    M.scalars[jp + "rms_current_A"] = agg[i].worst[1].value;
    M.scalars[jp + "peak_motor_speed_radps"] = agg[i].worst[2].value;
    M.scalars[jp + "peak_current_no_friction_A"] = agg[i].peak_current_no_friction;
  }
}

// The plot_fruits evaluated fruits of a design whose profiles are plotted: those a drive limit
// stops first (the profiles that show why), then the picked ones, each in fruit order.
std::vector<int> plottedFruits(const DesignResult& d, int plot_fruits) {
  std::vector<int> plotted;
  for (const bool failed : {true, false})
    for (const FruitResult& f : d.fruits)
      if (f.evaluated() && f.with_friction.feasible != failed &&
          static_cast<int>(plotted.size()) < plot_fruits)
        plotted.push_back(f.fruit);
  return plotted;
}

// A plot over t [s] (its panels to be added).
report::PlotSpec timePlot(const std::string& title) {
  report::PlotSpec spec;
  spec.title = title;
  spec.x_label = "t [s]";
  return spec;
}

// One series per joint of a fruit's profile `rows` (every `stride`-th sample), coloured by joint.
std::vector<report::PlotSeries> jointSeries(const Model& model,
                                            const std::vector<JointVector>& rows, double dt,
                                            int stride) {
  std::vector<report::PlotSeries> series = profileSeries(model, rows, dt, "", stride);
  for (std::size_t i = 0; i < series.size(); ++i)
    series[i].colour = report::seriesColour(static_cast<int>(i));
  return series;
}

// Joint efforts of one fruit: revolute joints [N m] and prismatic joints [N] in panels of their
// own.
report::PlotSpec effortPlot(const Model& model, const FruitResult& f, const std::string& what,
                            double dt, int stride) {
  const auto effort = jointSeries(model, f.with_friction.effort, dt, stride);
  report::PlotSpec ep = timePlot(what + ": joint efforts Q with friction");
  for (const bool prismatic : {false, true}) {
    report::PlotPanel panel;
    panel.y_label = prismatic ? "lift force [N]" : "joint torque [N m]";
    for (int i = 0; i < model.dof(); ++i)
      if ((model.joints[i].type == JointType::Prismatic) == prismatic)
        panel.series.push_back(effort[i]);
    if (!panel.series.empty()) ep.panels.push_back(panel);
  }
  return ep;
}

// Motor currents of one fruit: one panel per driven joint with its drive's current limits.
report::PlotSpec currentPlot(const Model& model, const FruitResult& f, const std::string& what,
                             double dt, int stride) {
  const auto current = jointSeries(model, f.with_friction.current, dt, stride);
  report::PlotSpec cp = timePlot(what + ": motor currents with friction and the drive limits");
  cp.panel_height = 120;
  for (int i = 0; i < model.dof(); ++i) {
    report::PlotPanel panel;
    panel.title = model.joints[i].name;
    panel.y_label = "I [A]";
    panel.series.push_back(current[i]);
    panel.series.back().label = "motor current";
    for (const Drive& dr : model.drives) {
      if (dr.joint != model.joints[i].name) continue;
      if (dr.peak_current_A > 0) {
        panel.lines.push_back({dr.peak_current_A, "peak limit", true, report::Rgb{214, 39, 40}});
        panel.lines.push_back({-dr.peak_current_A, "", true, report::Rgb{214, 39, 40}});
      }
      if (dr.continuous_current_A > 0) {
        panel.lines.push_back(
            {dr.continuous_current_A, "continuous limit", true, report::Rgb{255, 127, 14}});
        panel.lines.push_back({-dr.continuous_current_A, "", true, report::Rgb{255, 127, 14}});
      }
    }
    cp.panels.push_back(panel);
  }
  return cp;
}

// Fig. 4.1: one joint's motor current with and without friction (joint 3 as in the thesis).
report::PlotSpec frictionPlot(const Model& model, const FruitResult& f, const std::string& what,
                              double dt, int stride) {
  const int jf = std::min(2, model.dof() - 1);
  auto a = profileSeries(model, f.with_friction.current, dt, " with friction", stride);
  auto b = profileSeries(model, f.without_friction.current, dt, " without friction", stride);
  report::PlotSpec fp =
      timePlot(what + ": " + model.joints[jf].name + " with and without friction");
  fp.panels = {report::PlotPanel{"", "motor current [A]", {a[jf], b[jf]}, {}, false, std::nullopt}};
  fp.panels[0].series[1].dashed = true;
  return fp;
}

// Writes the profile CSV and the effort, current and friction plots of each plotted fruit.
void writeFruitPlots(const Model& model, const DesignResult& d, const std::vector<int>& plotted,
                     double dt, int stride, Writer& out) {
  for (const FruitResult& f : d.fruits) {
    if (std::find(plotted.begin(), plotted.end(), f.fruit) == plotted.end()) continue;
    const std::string fb = model.name + "_fruit" + std::to_string(f.fruit);
    out.text("harvest/" + fb + "_profile.csv", profileCsv(model, f, dt));
    const std::string what = model.name + " fruit " + std::to_string(f.fruit);
    out.text("harvest/" + fb + "_effort.svg",
             report::plot(effortPlot(model, f, what, dt, stride)).svg);
    out.text("harvest/" + fb + "_current.svg",
             report::plot(currentPlot(model, f, what, dt, stride)).svg);
    out.text("harvest/" + fb + "_friction.svg",
             report::plot(frictionPlot(model, f, what, dt, stride)).svg);
  }
}

// A joint's effort with its unit: "12.34 N m" (revolute), "456.78 N" (prismatic).
std::string effortText(const Model& model, int i, double q) {
  return report::fixed(q, 2) + (model.joints[i].type == JointType::Revolute ? " N m" : " N");
}

// The design's per-fruit table.
std::vector<std::vector<std::string>> fruitRows(const Model& model, const DesignResult& d) {
  std::vector<std::vector<std::string>> rows;
  for (const FruitResult& f : d.fruits) {
    rows.push_back({std::to_string(f.fruit),
                    report::fixed(f.p_fruit_W.x(), 3) + ", " + report::fixed(f.p_fruit_W.y(), 3) +
                        ", " + report::fixed(f.p_fruit_W.z(), 3),
                    f.limit_joint >= 0
                        ? f.status + " (" + model.joints[f.limit_joint].name + " at " +
                              jointLimitText(model, f.limit_joint, f.limit_q) + ")"
                        : f.status,
                    f.evaluated() ? failureText(model, f.with_friction) : "-",
                    f.evaluated() ? failureText(model, f.without_friction) : "-",
                    f.evaluated() ? report::scientific(f.max_position_error_m, 2) : "-"});
  }
  return rows;
}

// The design's per-joint table: worst over the evaluated fruits (with friction).
std::vector<std::vector<std::string>> jointRows(const Model& model,
                                                const std::vector<JointAggregate>& agg) {
  std::vector<std::vector<std::string>> rows;
  for (int i = 0; i < model.dof(); ++i) {
    const JointAggregate& a = agg[i];
    if (!a.has_drive) {
      rows.push_back({model.joints[i].name, effortText(model, i, a.peak_effort), "no drive", "", "",
                      "", "", "", "", ""});
      continue;
    }
    const auto& pc = a.worst[0];
    const auto& rc = a.worst[1];
    const auto& sc = a.worst[2];
    const auto& vc = a.worst[3];
    rows.push_back({model.joints[i].name, effortText(model, i, a.peak_effort),
                    report::fixed(pc.value, 2) + " / " + limitText(pc, 1), marginText(pc),
                    report::fixed(rc.value, 2) + " / " + limitText(rc, 1), marginText(rc),
                    report::fixed(sc.value, 0) + " / " + limitText(sc, 0), marginText(sc),
                    report::fixed(vc.value, 1) + " / " + limitText(vc, 0), marginText(vc),
                    report::fixed(a.peak_current_no_friction, 2),
                    a.has_friction_share ? report::percent(a.friction_share, 0) : "-",
                    std::to_string(a.exceeded_fruits)});
  }
  return rows;
}

// The design's report section: fruit counts, the per-fruit and per-joint tables, plot links.
report::Document designDocument(const Model& model, const DesignResult& d, const FruitCounts& c,
                                const std::vector<JointAggregate>& agg,
                                const std::vector<int>& plotted) {
  report::Document doc;
  doc.heading(2, model.name)
      .paragraph("Fruits evaluated: " + std::to_string(c.evaluated) + " of " +
                 std::to_string(d.fruits.size()) +
                 "; feasible with friction: " + std::to_string(c.feasible) +
                 ", without friction: " + std::to_string(c.feasible_nf) + ".")
      .table({"fruit", "position [m]", "status", "with friction (fails first)", "without friction",
              ">max TCP error [m]"},
             fruitRows(model, d))
      .paragraph("Per joint, worst over the evaluated fruits (with friction):")
      .table({"joint", ">peak Q", ">peak I [A] / limit", ">margin", ">RMS I [A] / limit", ">margin",
              ">motor speed [rad/s] / limit", ">margin", ">voltage [V] / limit", ">margin",
              ">peak I no friction [A]", ">friction share", ">fruits over a limit"},
             jointRows(model, agg))
      .paragraph(
          "friction share: the share of the peak current that friction adds, (peak |I| with "
          "friction - peak |I| without) / peak |I| with friction, the largest over the evaluated "
          "fruits; negative where friction lowers the peak (it works against a load that drives "
          "the joint). Thesis Fig. 4.1 gives a torque difference with and without friction of up "
          "to 50 % along one trajectory of joint 3.");
  for (int f : plotted) {
    const FruitResult& fr = d.fruits[f];
    const std::string what = model.name + " fruit " + std::to_string(f),
                      file = model.name + "_fruit" + std::to_string(f);
    doc.paragraph("Fruit " + std::to_string(f) + " (" +
                  (fr.with_friction.feasible ? "picked"
                                             : "fails: " + failureText(model, fr.with_friction)) +
                  "):")
        .figures({{what + " current", file + "_current.svg"},
                  {what + " friction", file + "_friction.svg"}});
  }
  return doc;
}

// The design's entry of summary.json (counts, fruits, joints), without the holding grid.
ordered_json designJson(const Model& model, const DesignResult& d, const FruitCounts& c,
                        const std::vector<JointAggregate>& agg) {
  ordered_json dj;
  dj["design"] = model.name;
  dj["evaluated"] = c.evaluated;
  dj["feasible"] = c.feasible;
  dj["feasible_no_friction"] = c.feasible_nf;
  dj["fruits"] = ordered_json::array();
  std::vector<std::string> assumed;  // the design's assumptions that a failure rests on
  for (const FruitResult& f : d.fruits) {
    ordered_json fj = {{"fruit", f.fruit},
                       {"p_W", {f.p_fruit_W.x(), f.p_fruit_W.y(), f.p_fruit_W.z()}},
                       {"status", f.status}};
    const std::vector<std::string> rests_on = failureAssumptions(model, f);
    if (f.limit_joint >= 0) {
      fj["limit_joint"] = model.joints[f.limit_joint].name;
      fj["limit"] = f.limit_q;
      fj["limit_text"] = jointLimitText(model, f.limit_joint, f.limit_q);
    }
    if (f.limit_joint >= 0 || (f.evaluated() && !f.with_friction.feasible))
      fj["limit_assumed"] = !rests_on.empty();
    for (const std::string& a : rests_on)
      if (std::find(assumed.begin(), assumed.end(), a) == assumed.end()) assumed.push_back(a);
    if (f.evaluated()) {
      fj["feasible"] = f.with_friction.feasible;
      fj["feasible_no_friction"] = f.without_friction.feasible;
      if (!f.with_friction.feasible) {
        fj["failing_joint"] = model.joints[f.with_friction.failing_joint].name;
        fj["failing_quantity"] = toString(f.with_friction.failing_quantity);
        fj["failure_time_s"] = f.with_friction.failure_time_s;
      }
      fj["max_position_error_m"] = f.max_position_error_m;
    }
    dj["fruits"].push_back(fj);
  }
  dj["assumptions"] = assumed;
  dj["joints"] = ordered_json::array();
  for (int i = 0; i < model.dof(); ++i) {
    ordered_json jj = {{"joint", model.joints[i].name},
                       {"has_drive", agg[i].has_drive},
                       {"peak_effort", agg[i].peak_effort}};
    for (int q = 0; q < kDriveQuantityCount; ++q) {
      const QuantityCheck& qc = agg[i].worst[q];
      ordered_json cj = {{"value", qc.value}, {"limit", qc.limit}};
      cj["margin"] = qc.checked ? ordered_json(qc.margin) : ordered_json(nullptr);
      jj[toString(static_cast<DriveQuantity>(q))] = cj;
    }
    jj["peak_current_no_friction"] = agg[i].peak_current_no_friction;
    jj["friction_share"] =
        agg[i].has_friction_share ? ordered_json(agg[i].friction_share) : ordered_json(nullptr);
    dj["joints"].push_back(jj);
  }
  return dj;
}

// Why a fruit was not picked, in words: the limit that stopped it (and whether the design assumes
// that limit), or the approach's status.
std::string missText(const ordered_json& f) {
  auto words = [](std::string id) {  // "rms_current" -> "RMS current"
    std::replace(id.begin(), id.end(), '_', ' ');
    return id.rfind("rms ", 0) == 0 ? "RMS " + id.substr(4) : id;
  };
  const std::string assumed = f.value("limit_assumed", false) ? " (an assumed limit)" : "";
  if (f.contains("limit_joint"))
    return "the tracking reached " + f["limit_joint"].get<std::string>() + "'s joint limit " +
           f.value("limit_text", "") + assumed;
  if (f.contains("failing_joint"))
    return f["failing_joint"].get<std::string>() + " " + words(f.value("failing_quantity", "")) +
           " over its limit" + assumed;
  return words(f.value("status", ""));
}

// The design's misses, fruits with the same reason together: "fruits 0, 1: <why>; fruit 4: ...".
std::string missesText(const ordered_json& d) {
  std::vector<std::pair<std::string, std::vector<int>>> by_why;
  for (const auto& f : d["fruits"]) {
    if (f.value("feasible", false)) continue;
    const std::string why = missText(f);
    auto it =
        std::find_if(by_why.begin(), by_why.end(), [&](const auto& p) { return p.first == why; });
    if (it == by_why.end()) it = by_why.insert(by_why.end(), {why, {}});
    it->second.push_back(f.value("fruit", 0));
  }
  std::string out;
  for (const auto& [why, fruits] : by_why) {
    out += std::string(out.empty() ? "" : "; ") + (fruits.size() > 1 ? "fruits " : "fruit ");
    for (std::size_t k = 0; k < fruits.size(); ++k)
      out += (k ? ", " : "") + std::to_string(fruits[k]);
    out += ": " + why;
  }
  return out;
}

}  // namespace

// The stage's answer (StageResult::answer) from its summary: per design, the fruits it picks
// within its drives' limits and why each other fruit fails (the joint and the limit that stopped
// it, whether that limit is assumed, or the approach's status); a design that picks none is a
// warning. The design assumptions the misses rest on go to StageResult::assumptions.
void harvestAnswer(const ordered_json& js, StageResult& sum) {
  const long fruits = js["row"].value("fruits", 0L);
  for (const auto& d : js["designs"]) {
    const std::string name = d.value("design", "");
    const long feasible = d.value("feasible", 0L);
    const std::string why = missesText(d);
    sum.answer.push_back("`" + name + "` picks " + std::to_string(feasible) + " of the " +
                         std::to_string(fruits) + " fruits within its drives' limits (" +
                         std::to_string(d.value("evaluated", 0L)) + " approached)" +
                         (why.empty() ? "." : "; misses " + why + "."));
    if (feasible == 0)
      sum.warnings.push_back("`" + name + "` picks none of the " + std::to_string(fruits) +
                             " fruits.");
    if (d.contains("assumptions"))
      for (const auto& a : d["assumptions"])
        sum.assumptions.push_back("`" + name + "`: " + a.get<std::string>());
  }
}

// Evaluates each selected design through the work units, writes its files and report sections,
// then report.md and summary.json.
StageResult runHarvestStage(const StageContext& ctx, const HarvestOptions& options,
                            std::vector<DesignResult>* results) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  Writer out(ctx.output_dir);  // files under harvest/
  const GreenhouseRow row = sampleGreenhouseRow(options.row);
  const double dt = 1.0 / options.rate_Hz;
  const int stride = std::max(1, static_cast<int>(std::lround(options.rate_Hz / 200.0)));
  report::Document designs;  // the designs' sections
  ordered_json js = summaryHead(ctx, options, row);
  std::vector<const Model*> models;
  std::vector<DesignResult> done;

  for (const StudyDesign& sd : ctx.study.designs) {
    const Model& model = sd.model;
    if (!selected(options, model)) continue;
    if (model.inertias.empty())
      throw InputError(
          model.file, 0, "inertia",
          "design '" + model.name + "' has no [[inertia]] data; the harvest stage needs it");
    DesignResult d = unitDesign(ctx, model, options, row, sum.units_resumed);
    out.text("harvest/" + model.name + "_fruits.csv", fruitCsv(model, d));
    const FruitCounts counts = countFruits(d);
    const std::vector<JointAggregate> agg = aggregate(model, d);
    addDesignMetrics(model, d, counts, agg, sum.metrics);
    const std::vector<int> plotted = plottedFruits(d, options.plot_fruits);
    writeFruitPlots(model, d, plotted, dt, stride, out);
    designs.append(designDocument(model, d, counts, agg, plotted));
    ordered_json dj = designJson(model, d, counts, agg);
    if (options.grid) {  // holding-load grid
      const HoldingSummary h = writeHoldingGrid(model, *options.grid, d, out, sum.metrics);
      designs.append(h.doc);
      sum.view.push_back(h.view);
      dj["grid"] = {{"points", h.points},
                    {"reachable", h.reachable},
                    {"drive_limited", h.limited},
                    {"max_current_ratio", h.max_ratio}};
    }
    js["designs"].push_back(dj);
    models.push_back(&model);
    done.push_back(std::move(d));
  }
  if (!sum.view.empty()) {
    sum.view_about =
        "The points are the holding grid's points in the world frame, coloured by whether the "
        "drives hold the arm there (static: gravity and payload) or by the revolute joints' "
        "largest current over its continuous limit; unreachable points are not drawn; the arm "
        "stands at its zero pose.";
    sum.view_value_label = "current ratio";
  }
  std::vector<const DesignResult*> done_ptrs;
  for (const DesignResult& d : done) done_ptrs.push_back(&d);
  harvestAnswer(js, sum);
  out.report("harvest/report.md", reportIntro(ctx, options, row)
                                      .append(writeFruitOutcomeFigure(models, done_ptrs, out))
                                      .append(designs));
  if (results)
    for (DesignResult& d : done) results->push_back(std::move(d));
  out.text("harvest/summary.json", js.dump(2) + "\n");
  sum.files = out.files();
  sum.reports = out.reports();
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace armstudy::harvest
