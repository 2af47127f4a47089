#include "stages/harvest/harvest_report.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/angles.hpp"
#include "common/format.hpp"
#include "io/vtk_io.hpp"
#include "model/model_notes.hpp"
#include "report/arm_drawing.hpp"
#include "report/markdown.hpp"
#include "study/scene.hpp"

namespace armstudy::harvest {

namespace {

bool isRevolute(const Model& model, int i) { return model.joints[i].type == JointType::Revolute; }

}  // namespace

std::string marginText(const QuantityCheck& c) {
  return c.checked ? report::percent(c.margin, 1) : "n/a";
}
std::string limitText(const QuantityCheck& c, int decimals) {
  return c.checked ? report::fixed(c.limit, decimals) : "-";
}

std::vector<JointAggregate> aggregate(const Model& model, const DesignResult& d) {
  const int n = model.dof();
  std::vector<JointAggregate> agg(n);
  for (const FruitResult& f : d.fruits) {
    if (!f.evaluated()) continue;
    for (int i = 0; i < n; ++i) {
      const JointDriveSummary& js = f.with_friction.joints[i];
      const JointDriveSummary& jn = f.without_friction.joints[i];
      JointAggregate& a = agg[i];
      a.has_drive = js.has_drive;
      a.peak_effort = std::max(a.peak_effort, js.peak_effort);
      bool any = false;
      for (int q = 0; q < kDriveQuantityCount; ++q) {
        const QuantityCheck& c = js.checks[q];
        QuantityCheck& w = a.worst[q];
        if (c.value >= w.value || !w.checked) {
          const bool first = !w.checked && w.value == 0;
          if (c.value >= w.value || first) w = c;
        }
        any = any || c.exceeded;
      }
      if (any) ++a.exceeded_fruits;
      a.peak_current_no_friction =
          std::max(a.peak_current_no_friction, jn.check(DriveQuantity::PeakCurrent).value);
      if (!f.with_friction.current.empty() && !f.without_friction.current.empty()) {
        // The share of the peak current that friction adds: (peak |I_f| - peak |I_nf|) / peak |I_f|
        // (at most 1; negative where friction lowers the peak, working against a load that drives
        // the joint).
        double peak_f = 0, peak_nf = 0;
        for (size_t k = 0; k < f.with_friction.current.size(); ++k)
          peak_f = std::max(peak_f, std::abs(f.with_friction.current[k][i]));
        for (size_t k = 0; k < f.without_friction.current.size(); ++k)
          peak_nf = std::max(peak_nf, std::abs(f.without_friction.current[k][i]));
        if (peak_f > 0) {
          const double share = (peak_f - peak_nf) / peak_f;
          a.friction_share = a.has_friction_share ? std::max(a.friction_share, share) : share;
          a.has_friction_share = true;
        }
      }
    }
  }
  return agg;
}

std::string failureText(const Model& model, const DriveFeasibility& r) {
  if (r.feasible) return "feasible";
  return model.joints[r.failing_joint].name + " " + toString(r.failing_quantity) + " at " +
         report::fixed(r.failure_time_s, 3) + " s";
}

std::string fruitCsv(const Model& model, const DesignResult& d) {
  std::ostringstream s;
  const int n = model.dof();
  s << "fruit,x_m,y_m,z_m,status,feasible,failing_joint,failing_quantity,failure_time_s,"
       "feasible_no_friction,max_position_error_m,max_orientation_error_rad";
  for (int i = 0; i < n; ++i) s << ",peak_current_A_" << model.joints[i].name;
  for (int i = 0; i < n; ++i) s << ",rms_current_A_" << model.joints[i].name;
  for (int i = 0; i < n; ++i) s << ",peak_current_no_friction_A_" << model.joints[i].name;
  s << "\n";
  for (const FruitResult& f : d.fruits) {
    s << f.fruit << "," << formatGOr(f.p_fruit_W.x(), 9, "nan") << ","
      << formatGOr(f.p_fruit_W.y(), 9, "nan") << "," << formatGOr(f.p_fruit_W.z(), 9, "nan") << ","
      << f.status << ",";
    if (f.evaluated()) {
      const auto& r = f.with_friction;
      s << (r.feasible ? 1 : 0) << "," << (r.feasible ? "" : model.joints[r.failing_joint].name)
        << "," << (r.feasible ? "" : toString(r.failing_quantity)) << ","
        << (r.feasible ? "" : formatGOr(r.failure_time_s, 9, "nan")) << ","
        << (f.without_friction.feasible ? 1 : 0) << ","
        << formatGOr(f.max_position_error_m, 9, "nan") << ","
        << formatGOr(f.max_orientation_error_rad, 9, "nan");
      for (int i = 0; i < n; ++i)
        s << "," << formatGOr(r.joints[i].check(DriveQuantity::PeakCurrent).value, 9, "nan");
      for (int i = 0; i < n; ++i)
        s << "," << formatGOr(r.joints[i].check(DriveQuantity::RmsCurrent).value, 9, "nan");
      for (int i = 0; i < n; ++i)
        s << ","
          << formatGOr(f.without_friction.joints[i].check(DriveQuantity::PeakCurrent).value, 9,
                       "nan");
    } else if (f.limit_joint >= 0) {  // the tracking stopped at this joint's limit
      s << "," << model.joints[f.limit_joint].name << ",joint_limit,,,,";
      for (int i = 0; i < 3 * n; ++i) s << ",";
    }
    s << "\n";
  }
  return s.str();
}

std::string profileCsv(const Model& model, const FruitResult& f, double dt) {
  const int n = model.dof();
  const auto& a = f.with_friction;
  const auto& b = f.without_friction;
  std::ostringstream s;
  s << "t_s";
  const char* cols[] = {"effort", "current_A", "current_no_friction_A", "motor_speed_radps",
                        "voltage_V"};
  for (const char* c : cols)
    for (int i = 0; i < n; ++i) s << "," << c << "_" << model.joints[i].name;
  s << "\n";
  for (size_t k = 0; k < a.effort.size(); ++k) {
    s << formatGOr(k * dt, 9, "nan");
    for (int i = 0; i < n; ++i) s << "," << formatGOr(a.effort[k][i], 9, "nan");
    for (int i = 0; i < n; ++i) s << "," << formatGOr(a.current[k][i], 9, "nan");
    for (int i = 0; i < n; ++i) s << "," << formatGOr(b.current[k][i], 9, "nan");
    for (int i = 0; i < n; ++i) s << "," << formatGOr(a.motor_speed[k][i], 9, "nan");
    for (int i = 0; i < n; ++i) s << "," << formatGOr(a.voltage[k][i], 9, "nan");
    s << "\n";
  }
  return s.str();
}

// Every `stride`-th sample (plots stay small).
std::vector<report::PlotSeries> profileSeries(const Model& model,
                                              const std::vector<JointVector>& rows, double dt,
                                              const std::string& suffix, int stride) {
  std::vector<report::PlotSeries> out;
  for (int i = 0; i < model.dof(); ++i) {
    report::PlotSeries s;
    s.label = model.joints[i].name + suffix;
    for (size_t k = 0; k < rows.size(); k += stride) {
      s.x.push_back(k * dt);
      s.y.push_back(rows[k][i]);
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::string jointLimitText(const Model& model, int joint, double q) {
  if (isRevolute(model, joint)) {
    const double deg = toDegrees(q);
    return (deg > 0 ? "+" : "") + report::fixed(deg, 0) + " deg";
  }
  return (q > 0 ? "+" : "") + report::fixed(q, 3) + " m";
}

const char* assumptionTopic(DriveQuantity q) {
  switch (q) {
    case DriveQuantity::PeakCurrent:
    case DriveQuantity::RmsCurrent:
      return "current limits";
    case DriveQuantity::MotorSpeed:
      return "max_motor_speed";
    case DriveQuantity::Voltage:
      return "max_voltage";
  }
  return "";
}

std::vector<std::string> failureAssumptions(const Model& model, const FruitResult& f) {
  if (f.limit_joint >= 0) return notes::about(model, notes::kJointLimits);
  if (f.evaluated() && !f.with_friction.feasible)
    return notes::about(model, assumptionTopic(f.with_friction.failing_quantity));
  return {};
}

std::string fruitOutcome(const Model& model, const FruitResult& f) {
  const auto words = [](std::string s) {  // "motor_speed" -> "motor speed"
    std::replace(s.begin(), s.end(), '_', ' ');
    return s;
  };
  if (f.limit_joint >= 0) return "joint limit: " + model.joints[f.limit_joint].name;
  if (!f.evaluated()) return "not tracked: " + words(f.status);
  const DriveFeasibility& r = f.with_friction;
  if (r.feasible) return "picked";
  return "drive limit: " + model.joints[r.failing_joint].name + " " +
         words(toString(r.failing_quantity));
}

report::Drawing fruitOutcomeFigure(const std::vector<const Model*>& models,
                                   const std::vector<const DesignResult*>& results) {
  // One colour per outcome over all designs: "picked" first, the failures in name order.
  std::vector<std::string> outcomes{"picked"};
  double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo, y_lo = z_lo, y_hi = z_hi;
  for (std::size_t k = 0; k < models.size(); ++k)
    for (const FruitResult& f : results[k]->fruits) {
      const std::string o = fruitOutcome(*models[k], f);
      if (std::find(outcomes.begin(), outcomes.end(), o) == outcomes.end()) outcomes.push_back(o);
      z_lo = std::min(z_lo, f.p_fruit_W.z());
      z_hi = std::max(z_hi, f.p_fruit_W.z());
      y_lo = std::min(y_lo, f.p_fruit_W.y());
      y_hi = std::max(y_hi, f.p_fruit_W.y());
    }
  if (!(z_hi >= z_lo)) z_lo = z_hi = y_lo = y_hi = 0;  // no fruit
  std::sort(outcomes.begin() + 1, outcomes.end());
  // Picked in bluish green, the first failure in vermillion, the next ones in blue, orange, ...
  const auto colour = [&](const std::string& o) {
    const int at =
        static_cast<int>(std::find(outcomes.begin(), outcomes.end(), o) - outcomes.begin());
    return report::okabeIto(at == 0 ? 1 : at == 1 ? 0 : at);
  };
  const double pad = std::max(0.05, 0.06 * (z_hi - z_lo));
  report::PlotSpec p;
  p.title = "What became of each fruit";
  p.x_label = "y along the row, world frame [m]";
  p.panel_height = 200;
  for (std::size_t k = 0; k < models.size(); ++k) {
    report::PlotPanel panel;
    panel.title = models[k]->name;
    panel.y_label = "z (height) [m]";
    panel.y_range = std::array<double, 2>{z_lo - pad, z_hi + pad};
    // The row's extent, padded (a series drawn neither as line nor as dots), so that no fruit
    // sits on the frame.
    const double ypad = std::max(0.05, 0.06 * (y_hi - y_lo));
    report::PlotSeries extent;
    extent.lines = false;
    extent.x = {y_lo - ypad, y_hi + ypad};
    extent.y = {z_lo, z_lo};
    panel.series.push_back(std::move(extent));
    for (const std::string& o : outcomes) {
      report::PlotSeries s;
      s.label = o;
      s.colour = colour(o);
      s.lines = false;
      s.markers = true;
      for (const FruitResult& f : results[k]->fruits)
        if (fruitOutcome(*models[k], f) == o) {
          s.x.push_back(f.p_fruit_W.y());
          s.y.push_back(f.p_fruit_W.z());
          s.point_labels.push_back(std::to_string(f.fruit));  // its number in the tables
        }
      if (!s.x.empty()) panel.series.push_back(std::move(s));
    }
    p.panels.push_back(std::move(panel));
  }
  return report::plot(p);
}

report::Document writeFruitOutcomeFigure(const std::vector<const Model*>& models,
                                         const std::vector<const DesignResult*>& results,
                                         Writer& out) {
  if (models.empty()) return {};
  out.text("harvest/fruits.svg", fruitOutcomeFigure(models, results).svg);
  return report::Document()
      .paragraph(
          "Every fruit at its position in the row (world frame: y along the row, z up), marked by "
          "what became of it and labelled with its number; one panel per design on the same "
          "axes, the fruits' positions in the tables below and in `<design>_fruits.csv`.")
      .figures({{"What became of each fruit, per design", "fruits.svg"}});
}

namespace {

// The holding load sampled over a grid: the VTK image with its point arrays, and its counts.
struct HoldingImage {
  io::ImageGrid img;  // status, max_current_ratio, max_current_ratio_revolute, limiting_joint,
                      // holding_<joint>
  int reachable = 0, limited = 0;
  double max_ratio = 0;
  int max_ratio_joint = -1;
  std::vector<int> limiting_count;  // drive-limited grid points per limiting joint
};

// The units and legend lines of the holding image's field data.
std::vector<io::FieldStrings> holdingFieldData(const Model& model) {
  const int n = model.dof();
  std::vector<std::string> units{"position: m", "status: 1", "max_current_ratio: 1",
                                 "max_current_ratio_revolute: 1", "limiting_joint: 1"};
  std::vector<std::string> legend{
      "status 0: unreachable (every other quantity NaN, limiting_joint -1)",
      "status 1: the drives hold the pose", "status 2: a drive over its limit",
      "limiting_joint -1: none"};
  for (int i = 0; i < n; ++i) {
    units.push_back("holding_" + model.joints[i].name + (isRevolute(model, i) ? ": N m" : ": N"));
    legend.push_back("limiting_joint " + std::to_string(i) + ": " + model.joints[i].name);
  }
  return io::fieldData(units, legend);
}

// Fills the holding image from the grid points of a design result and counts the reachable,
// drive-limited points and the largest current ratio.
HoldingImage holdingImage(const Model& model, const HarvestGrid& g, const DesignResult& d) {
  HoldingImage hi;
  io::ImageGrid& img = hi.img;
  const int n = model.dof();
  img.dims = {g.axes[0].count(), g.axes[1].count(), g.axes[2].count()};
  for (int a = 0; a < 3; ++a) {
    img.origin[a] = g.axes[a].from;
    img.spacing[a] = g.axes[a].step;
  }
  const long np = img.points();
  io::NamedArray status{"status", io::ArrayType::Int32, 1, std::vector<double>(np)};
  io::NamedArray ratio{"max_current_ratio", io::ArrayType::Float64, 1, std::vector<double>(np)};
  // The lift carries the whole arm: its holding current hardly depends on the pose, so the map
  // also shows the largest ratio over the revolute joints.
  io::NamedArray ratio_rev{"max_current_ratio_revolute", io::ArrayType::Float64, 1,
                           std::vector<double>(np)};
  io::NamedArray limj{"limiting_joint", io::ArrayType::Int32, 1, std::vector<double>(np)};
  std::vector<io::NamedArray> hold;
  for (int i = 0; i < n; ++i)
    hold.push_back(
        {"holding_" + model.joints[i].name, io::ArrayType::Float64, 1, std::vector<double>(np)});
  hi.limiting_count.assign(n, 0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (long p = 0; p < np; ++p) {
    const GridPointResult& gp = d.grid[p];
    if (!gp.reachable) {
      status.values[p] = 0;
      ratio.values[p] = nan;
      ratio_rev.values[p] = nan;
      limj.values[p] = -1;
      for (auto& h : hold) h.values[p] = nan;
      continue;
    }
    ++hi.reachable;
    const bool ok = gp.holding.feasible;
    if (!ok) {
      ++hi.limited;
      ++hi.limiting_count[gp.holding.limiting_joint];
    }
    if (gp.holding.limiting_joint >= 0 && gp.holding.max_ratio > hi.max_ratio) {
      hi.max_ratio = gp.holding.max_ratio;
      hi.max_ratio_joint = gp.holding.limiting_joint;
    }
    status.values[p] = ok ? 1 : 2;
    ratio.values[p] = gp.holding.max_ratio;
    ratio_rev.values[p] = 0;
    for (int i = 0; i < n; ++i)
      if (isRevolute(model, i))
        ratio_rev.values[p] = std::max(ratio_rev.values[p], gp.holding.current_ratio[i]);
    limj.values[p] = gp.holding.limiting_joint;
    for (int i = 0; i < n; ++i) hold[i].values[p] = gp.holding.effort[i];
  }
  img.point_arrays = {status, ratio, ratio_rev, limj};
  for (auto& h : hold) img.point_arrays.push_back(std::move(h));
  img.field_data = holdingFieldData(model);
  return hi;
}

// The holding map's colours: the status colours of every map (reachable, torque limit, out of
// reach).
const report::Rgb kHoldable = report::categorical(0), kDriveLimit = report::categorical(5),
                  kUnreachable = report::categorical(1);

// Writes the status and revolute current-ratio maps over the first two axes with more than one
// value (the first slice of a 3-D grid) and returns their report part; without two such axes,
// only the paragraph with the counts.
report::Document writeHoldingMaps(const Model& model, const HarvestGrid& g, const HoldingImage& hi,
                                  Writer& out) {
  const io::ImageGrid& img = hi.img;
  const std::string base = model.name;
  const long np = img.points();
  const std::vector<double>& status = img.point_arrays[0].values;
  const std::vector<double>& ratio_rev = img.point_arrays[2].values;
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (img.dims[a] > 1) axes.push_back(a);
  if (axes.size() < 2)
    return report::Document().paragraph(
        "Static holding over the grid: " + std::to_string(hi.reachable) + " of " +
        std::to_string(np) + " points reachable, " + std::to_string(hi.limited) +
        " drive-limited.");
  const int a0 = axes[0], a1 = axes[1];
  auto index = [&](int u, int v) {
    std::array<long, 3> ijk{0, 0, 0};
    ijk[a0] = u;
    ijk[a1] = v;
    return ijk[0] + img.dims[0] * (ijk[1] + static_cast<long>(img.dims[1]) * ijk[2]);
  };
  const auto statusImg = report::renderCellMap(img.dims[a0], img.dims[a1], [&](int u, int v) {
    const int s = static_cast<int>(status[index(u, v)]);
    return s == 0 ? kUnreachable : s == 1 ? kHoldable : kDriveLimit;
  });
  // Figures with axes and legends (.svg, shown in the report; the same as .png).
  const char* an[3] = {"x", "y", "z"};
  auto figure = [&](const std::string& title) {
    report::MapFigure f;
    f.title = title;
    f.x = report::cellAxis(std::string(an[a0]) + " [m]", img.origin[a0],
                           img.origin[a0] + img.spacing[a0] * (img.dims[a0] - 1), img.spacing[a0]);
    f.y = report::cellAxis(std::string(an[a1]) + " [m]", img.origin[a1],
                           img.origin[a1] + img.spacing[a1] * (img.dims[a1] - 1), img.spacing[a1]);
    return f;
  };
  report::MapFigure status_fig = figure(model.name + ": static holding");
  status_fig.legend = {
      {kHoldable, "holdable"}, {kDriveLimit, "drive limit"}, {kUnreachable, "unreachable"}};
  const report::Drawing status_d =
      report::mapFigure(statusImg, status_fig, report::Format::svg_and_png);
  out.text("harvest/" + base + "_holding_map.png", status_d.png);
  out.text("harvest/" + base + "_holding_map.svg", status_d.svg);
  const auto ratioImg = report::renderCellMap(img.dims[a0], img.dims[a1], [&](int u, int v) {
    const double r = ratio_rev[index(u, v)];
    return std::isfinite(r) ? report::viridis(r / 1.5) : report::Rgb{200, 200, 200};
  });
  report::MapFigure ratio_fig = figure(model.name + ": max |I| / I_continuous (revolute joints)");
  ratio_fig.scale = report::ColourScale{report::viridis, 0, 1.5, "max |I| / I_continuous [1]"};
  ratio_fig.legend = {{report::Rgb{200, 200, 200}, "unreachable"}};
  const report::Drawing ratio_d =
      report::mapFigure(ratioImg, ratio_fig, report::Format::svg_and_png);
  out.text("harvest/" + base + "_holding_ratio.png", ratio_d.png);
  out.text("harvest/" + base + "_holding_ratio.svg", ratio_d.svg);
  std::ostringstream text;
  text << "Static holding (gravity + payload) over the grid, tool heading "
       << report::fixed(toDegrees(g.gamma_rad), 0) << " deg: " << hi.reachable << " of " << np
       << " points reachable, " << hi.limited
       << " of them drive-limited (|I| > continuous current). Map axes: " << an[a0]
       << " to the right, " << an[a1] << " upwards; " << report::hex(kHoldable) << " holdable, "
       << report::hex(kDriveLimit) << " drive limit, " << report::hex(kUnreachable)
       << " unreachable. Second map: max |I| / I_continuous over the revolute joints (viridis, 0 "
          "to 1.5; the lift's ratio is nearly constant, it carries the whole arm).";
  return report::Document()
      .paragraph(text.str())
      .figures(
          {{"holding map", base + "_holding_map.svg"}, {"ratio", base + "_holding_ratio.svg"}});
}

// The holding grid as a map of the 3-D view: every grid point with its status in the holding
// map's colours (categorical 0 holdable, 5 drive limit; unreachable points not drawn) and the
// revolute joints' largest current ratio; the grid's poses are not kept, so the arm stands at its
// zero pose.
report::ViewCloud holdingViewCloud(const Model& model, const HarvestGrid& g,
                                   const HoldingImage& hi) {
  const io::ImageGrid& img = hi.img;
  report::ViewCloud c;
  c.name = "static holding: " + model.name;
  c.value_quantity = "max |I| / I_continuous over the revolute joints";
  c.value_unit = "1";
  c.status_names = {"the drives hold the pose",           "", "", "", "",
                    "a drive over its continuous current"};
  double step = INFINITY;
  for (int a = 0; a < 3; ++a)
    if (img.dims[a] > 1) step = std::min(step, img.spacing[a]);
  c.point_size_m = std::isfinite(step) ? step : 0.02;
  const std::vector<double>& status = img.point_arrays[0].values;
  const std::vector<double>& ratio_rev = img.point_arrays[2].values;
  for (int k = 0; k < img.dims[2]; ++k)
    for (int j = 0; j < img.dims[1]; ++j)
      for (int i = 0; i < img.dims[0]; ++i) {
        const long p = i + img.dims[0] * (j + static_cast<long>(img.dims[1]) * k);
        c.p_W.push_back({img.origin[0] + i * img.spacing[0], img.origin[1] + j * img.spacing[1],
                         img.origin[2] + k * img.spacing[2]});
        const int s = static_cast<int>(status[p]);
        c.status.push_back(s == 1 ? 0 : s == 2 ? 5 : 1);  // status 1 has no name: not drawn
        c.value.push_back(ratio_rev[p]);
      }
  for (const Eigen::Vector3d& x : scene::skeletonPoints(model, report::zeroPose(model)))
    c.arm_W.push_back({x.x(), x.y(), x.z()});
  c.arm_caption = "arm: " + model.name +
                  " at its zero pose (each joint's zero clamped into its limits; the grid's "
                  "poses are not kept), tool heading " +
                  report::fixed(toDegrees(g.gamma_rad), 0) + " deg at every grid point.";
  return c;
}

}  // namespace

// Writes the holding image, adds the holding metrics, writes the maps and assembles the report
// paragraph with the limiting-joint table.
HoldingSummary writeHoldingGrid(const Model& model, const HarvestGrid& g, const DesignResult& d,
                                Writer& out, StudyMetrics& M) {
  HoldingSummary h;
  const int n = model.dof();
  const std::string base = model.name;
  const std::string mprefix = "harvest/" + model.name + "/";
  const HoldingImage hi = holdingImage(model, g, d);
  const long np = hi.img.points();
  io::writeVti(out.path("harvest/" + base + "_holding.vti"), hi.img);
  out.add("harvest/" + base + "_holding.vti");
  M.scalars[mprefix + "holding_reachable_fraction"] = hi.reachable / static_cast<double>(np);
  M.scalars[mprefix + "holding_drive_limited_fraction"] =
      hi.reachable > 0 ? hi.limited / static_cast<double>(hi.reachable) : 0.0;
  M.scalars[mprefix + "holding_max_current_ratio"] = hi.max_ratio;
  h.doc.paragraph("Largest static holding current over the reachable grid points: " +
                  report::percent(hi.max_ratio, 1) + " of the continuous limit" +
                  (hi.max_ratio_joint >= 0 ? " (" + model.joints[hi.max_ratio_joint].name + ")"
                                           : std::string()) +
                  ".");
  h.doc.append(writeHoldingMaps(model, g, hi, out));
  std::vector<std::vector<std::string>> lrows;
  for (int i = 0; i < n; ++i)
    if (hi.limiting_count[i] > 0)
      lrows.push_back({model.joints[i].name, std::to_string(hi.limiting_count[i])});
  if (!lrows.empty()) h.doc.table({"limiting joint", ">grid points"}, std::move(lrows));
  h.points = np;
  h.reachable = hi.reachable;
  h.limited = hi.limited;
  h.max_ratio = hi.max_ratio;
  h.view = holdingViewCloud(model, g, hi);
  return h;
}

}  // namespace armstudy::harvest
