#include "stages/harvest/harvest_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/errors.hpp"
#include "report/markdown.hpp"
#include "report/plot.hpp"
#include "stages/harvest/harvest_report.hpp"
#include "stages/harvest/harvest_units.hpp"
#include "study/writer.hpp"

namespace armstudy::harvest {

using nlohmann::ordered_json;

StageResult runHarvestStage(const StageContext& ctx, const HarvestOptions& options,
                            std::vector<DesignResult>* results) {
  const auto t0 = std::chrono::steady_clock::now();
  StageResult sum;
  Writer out(ctx.output_dir);  // files under harvest/
  const GreenhouseRow row = sampleGreenhouseRow(options.row);
  const double dt = 1.0 / options.rate_Hz;
  const int stride = std::max(1, static_cast<int>(std::lround(options.rate_Hz / 200.0)));

  std::ostringstream md;
  md << "# Harvest torque study: " << ctx.study.name << "\n\n"
     << "Approaches to a greenhouse row sampled from thesis Table 2.2 (seed " << options.row.seed
     << ", " << row.fruits.size() << " fruits on " << row.stems_xy.size()
     << " stems), planned with the heuristic planner of section 5.3.2 (r_e = "
     << report::fixed(options.approach.entry_radius_m, 3) << " m, s_a = " << options.approach.s_a
     << ", s_e = " << options.approach.s_e << ", T = " << options.approach.duration_s
     << " s), tracked with the null-space IK (joint limits weight " << options.w_joint_limits
     << ", manipulability weight " << options.w_manipulability << ") at "
     << report::fixed(options.rate_Hz, 0)
     << " Hz, inverse dynamics and drive chain per joint (docs/dynamics.md). Margins are "
        "(limit - value) / limit; n/a = limit not given in the design.\n\n";

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

  for (const StudyDesign& sd : ctx.study.designs) {
    const Model& model = sd.model;
    if (!options.designs.empty() && std::find(options.designs.begin(), options.designs.end(),
                                              model.name) == options.designs.end())
      continue;
    if (model.inertias.empty())
      throw InputError(
          model.file, 0, "inertia",
          "design '" + model.name + "' has no [[inertia]] data; the harvest stage needs it");
    DesignResult d = unitDesign(ctx, model, options, row, sum.units_resumed);
    const int n = model.dof();
    const std::string base = model.name;
    const std::string mprefix = "dynamics/" + model.name + "/";

    out.text("harvest/" + base + "_fruits.csv", fruitCsv(model, d));

    int evaluated = 0, feasible = 0, feasible_nf = 0;
    std::vector<std::uint8_t> flags;
    for (const FruitResult& f : d.fruits) {
      flags.push_back(f.evaluated() && f.with_friction.feasible ? 1 : 0);
      if (!f.evaluated()) continue;
      ++evaluated;
      feasible += f.with_friction.feasible;
      feasible_nf += f.without_friction.feasible;
    }
    const double nfr = std::max<double>(1, static_cast<double>(d.fruits.size()));
    auto& M = sum.metrics;
    M.scalars[mprefix + "evaluated_fraction"] = evaluated / nfr;
    M.scalars[mprefix + "feasible_fraction"] = feasible / nfr;
    M.scalars[mprefix + "feasible_fraction_no_friction"] = feasible_nf / nfr;
    M.flags[mprefix + "fruit_feasible"] = flags;
    const std::vector<JointAggregate> agg = aggregate(model, d);
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

    // Plots and profiles of the first fruits.
    std::vector<int> plotted;  // the first plot_fruits evaluated fruits
    for (const FruitResult& f : d.fruits)
      if (f.evaluated() && static_cast<int>(plotted.size()) < options.plot_fruits)
        plotted.push_back(f.fruit);
    for (const FruitResult& f : d.fruits) {
      if (std::find(plotted.begin(), plotted.end(), f.fruit) == plotted.end()) continue;
      const std::string fb = base + "_fruit" + std::to_string(f.fruit);
      out.text("harvest/" + fb + "_profile.csv", profileCsv(model, f, dt));
      const std::string what = model.name + " fruit " + std::to_string(f.fruit);
      // Efforts: revolute joints [N m] and prismatic joints [N] in panels of their own.
      const auto effort = profileSeries(model, f.with_friction.effort, dt, "", stride);
      report::PlotSpec ep;
      ep.title = what + ": joint efforts Q with friction";
      ep.x_label = "t [s]";
      for (const bool prismatic : {false, true}) {
        report::PlotPanel panel;
        panel.y_label = prismatic ? "lift force [N]" : "joint torque [N m]";
        for (int i = 0; i < n; ++i)
          if ((model.joints[i].type == JointType::Prismatic) == prismatic) {
            panel.series.push_back(effort[i]);
            panel.series.back().colour = report::seriesColour(i);
          }
        if (!panel.series.empty()) ep.panels.push_back(panel);
      }
      out.text("harvest/" + fb + "_effort.svg", report::plot(ep).svg);
      // Motor currents: one panel per driven joint with its drive's current limits.
      const auto current = profileSeries(model, f.with_friction.current, dt, "", stride);
      report::PlotSpec cp;
      cp.title = what + ": motor currents with friction and the drive limits";
      cp.x_label = "t [s]";
      cp.panel_height = 120;
      for (int i = 0; i < n; ++i) {
        report::PlotPanel panel;
        panel.title = model.joints[i].name;
        panel.y_label = "I [A]";
        panel.series.push_back(current[i]);
        panel.series.back().label = "motor current";
        panel.series.back().colour = report::seriesColour(i);
        for (const Drive& dr : model.drives) {
          if (dr.joint != model.joints[i].name) continue;
          if (dr.peak_current_A > 0) {
            panel.lines.push_back({dr.peak_current_A, "peak limit", true, report::Rgb{214, 39, 40}});
            panel.lines.push_back({-dr.peak_current_A, "", true, report::Rgb{214, 39, 40}});
          }
          if (dr.continuous_current_A > 0) {
            panel.lines.push_back({dr.continuous_current_A, "continuous limit", true, report::Rgb{255, 127, 14}});
            panel.lines.push_back({-dr.continuous_current_A, "", true, report::Rgb{255, 127, 14}});
          }
        }
        cp.panels.push_back(panel);
      }
      out.text("harvest/" + fb + "_current.svg", report::plot(cp).svg);
      // Fig. 4.1: one joint with and without friction (joint 3 as in the thesis).
      const int jf = std::min(2, n - 1);
      auto a = profileSeries(model, f.with_friction.current, dt, " with friction", stride);
      auto b = profileSeries(model, f.without_friction.current, dt, " without friction", stride);
      report::PlotSpec fp;
      fp.title = what + ": " + model.joints[jf].name + " with and without friction";
      fp.x_label = "t [s]";
      fp.panels = {report::PlotPanel{"", "motor current [A]", {a[jf], b[jf]}, {}, false}};
      fp.panels[0].series[1].dashed = true;
      out.text("harvest/" + fb + "_friction.svg", report::plot(fp).svg);
    }

    // Report: per-fruit and per-joint tables.
    md << "## " << model.name << "\n\n"
       << "Fruits evaluated: " << evaluated << " of " << d.fruits.size()
       << "; feasible with friction: " << feasible << ", without friction: " << feasible_nf
       << ".\n\n";
    std::vector<std::vector<std::string>> rows;
    for (const FruitResult& f : d.fruits) {
      rows.push_back({std::to_string(f.fruit),
                      report::fixed(f.p_fruit_W.x(), 3) + ", " + report::fixed(f.p_fruit_W.y(), 3) +
                          ", " + report::fixed(f.p_fruit_W.z(), 3),
                      f.status, f.evaluated() ? failureText(model, f.with_friction) : "-",
                      f.evaluated() ? failureText(model, f.without_friction) : "-",
                      f.evaluated() ? report::scientific(f.max_position_error_m, 2) : "-"});
    }
    md << report::markdownTable({"fruit", "position [m]", "status", "with friction (fails first)",
                                 "without friction", ">max TCP error [m]"},
                                rows)
       << "\n";
    rows.clear();
    for (int i = 0; i < n; ++i) {
      const JointAggregate& a = agg[i];
      if (!a.has_drive) {
        rows.push_back({model.joints[i].name, report::fixed(a.peak_effort, 2), "no drive", "", "",
                        "", "", "", "", ""});
        continue;
      }
      const auto& pc = a.worst[0];
      const auto& rc = a.worst[1];
      const auto& sc = a.worst[2];
      const auto& vc = a.worst[3];
      rows.push_back({model.joints[i].name, report::fixed(a.peak_effort, 2),
                      report::fixed(pc.value, 2) + " / " + limitText(pc, 1), marginText(pc),
                      report::fixed(rc.value, 2) + " / " + limitText(rc, 1), marginText(rc),
                      report::fixed(sc.value, 0) + " / " + limitText(sc, 0), marginText(sc),
                      report::fixed(vc.value, 1) + " / " + limitText(vc, 0), marginText(vc),
                      report::fixed(a.peak_current_no_friction, 2),
                      report::percent(a.friction_share, 0), std::to_string(a.exceeded_fruits)});
    }
    md << "Per joint, worst over the evaluated fruits (with friction):\n\n"
       << report::markdownTable(
              {"joint", ">peak Q [N m, N]", ">peak I [A] / limit", ">margin", ">RMS I [A] / limit",
               ">margin", ">motor speed [rad/s] / limit", ">margin", ">voltage [V] / limit",
               ">margin", ">peak I no friction [A]", ">friction share", ">fruits over a limit"},
              rows)
       << "\nfriction share = max_t |I_friction - I_frictionless| / max_t |I_friction| over the "
          "evaluated fruits (thesis Fig. 4.1 reports up to 50 % for joint 3).\n\n";
    for (int f : plotted)
      md << "![" << model.name << " fruit " << f << " current](" << base << "_fruit" << f
         << "_current.svg) ![friction](" << base << "_fruit" << f << "_friction.svg)\n\n";

    ordered_json dj;
    dj["design"] = model.name;
    dj["evaluated"] = evaluated;
    dj["feasible"] = feasible;
    dj["feasible_no_friction"] = feasible_nf;
    dj["fruits"] = ordered_json::array();
    for (const FruitResult& f : d.fruits) {
      ordered_json fj = {{"fruit", f.fruit},
                         {"p_W", {f.p_fruit_W.x(), f.p_fruit_W.y(), f.p_fruit_W.z()}},
                         {"status", f.status}};
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
    dj["joints"] = ordered_json::array();
    for (int i = 0; i < n; ++i) {
      ordered_json jj = {{"joint", model.joints[i].name},
                         {"has_drive", agg[i].has_drive},
                         {"peak_effort", agg[i].peak_effort}};
      for (int q = 0; q < kDriveQuantityCount; ++q) {
        const QuantityCheck& c = agg[i].worst[q];
        ordered_json cj = {{"value", c.value}, {"limit", c.limit}};
        cj["margin"] = c.checked ? ordered_json(c.margin) : ordered_json(nullptr);
        jj[toString(static_cast<DriveQuantity>(q))] = cj;
      }
      jj["peak_current_no_friction"] = agg[i].peak_current_no_friction;
      jj["friction_share"] = agg[i].friction_share;
      dj["joints"].push_back(jj);
    }

    if (options.grid) {  // holding-load grid
      const HoldingSummary h = writeHoldingGrid(model, *options.grid, d, out, sum.metrics);
      md << h.markdown;
      dj["grid"] = {{"points", h.points},
                    {"reachable", h.reachable},
                    {"drive_limited", h.limited},
                    {"max_current_ratio", h.max_ratio}};
    }
    js["designs"].push_back(dj);
    if (results) results->push_back(std::move(d));
  }
  out.text("harvest/report.md", md.str());
  out.text("harvest/summary.json", js.dump(2) + "\n");
  sum.files = out.files();
  sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sum;
}

}  // namespace armstudy::harvest
