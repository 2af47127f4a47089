#include "report/arm_drawing.hpp"

#include <algorithm>

#include "kinematics/kinematics.hpp"

namespace armstudy::report {

namespace {

constexpr double kFrameLengthShare =
    0.08;                                // frame axes and joint axes: this share of the arm's size
constexpr double kPanelHeight_px = 400;  // about the plot area's width: equal scale on both axes

// An invisible series that gives both axes of the panel the same span (equal scale in a square
// panel), centred on what the panel shows.
void equalScale(PlotPanel& p) {
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& s : p.series)
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      lo[0] = std::min(lo[0], s.x[k]), hi[0] = std::max(hi[0], s.x[k]);
      lo[1] = std::min(lo[1], s.y[k]), hi[1] = std::max(hi[1], s.y[k]);
    }
  const double half = 0.5 * std::max(hi[0] - lo[0], hi[1] - lo[1]);
  PlotSeries box;
  box.lines = false;
  for (int c = 0; c < 2; ++c) {
    const double mx = 0.5 * (lo[0] + hi[0]), my = 0.5 * (lo[1] + hi[1]);
    box.x.push_back(mx + (c ? half : -half));
    box.y.push_back(my + (c ? half : -half));
  }
  p.series.push_back(box);
}

// One view (a, b: the world axes drawn to the right and upwards) of the arm posed in `ws`.
PlotPanel view(const Model& m, const KinematicsWorkspace& ws, int a, int b, const char* title,
               double len) {
  PlotPanel p;
  p.title = title;
  p.y_label = std::string(b == 2 ? "z" : "y") + " [m]";
  auto segment = [&](const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const std::string& label,
                     Rgb colour, bool dashed) {
    PlotSeries s;
    s.label = label;
    s.x = {p0[a], p1[a]};
    s.y = {p0[b], p1[b]};
    s.colour = colour;
    s.dashed = dashed;
    p.series.push_back(s);
  };
  PlotSeries arm;
  arm.label = "links (base, joint frames, TCP)";
  arm.markers = true;
  arm.colour = Rgb{40, 40, 40};
  std::vector<Eigen::Vector3d> pts{m.T_WB.translation()};
  for (int i = 0; i < m.dof(); ++i) pts.push_back(ws.p_WF[i]);
  pts.push_back(ws.p_WT);
  for (const auto& pt : pts) arm.x.push_back(pt[a]), arm.y.push_back(pt[b]);
  p.series.push_back(arm);
  const Rgb axis_colour[3] = {{214, 39, 40}, {44, 160, 44}, {31, 119, 180}};
  const char* axis_label[3] = {"frame x", "frame y", "frame z"};
  for (int i = 0; i <= m.dof(); ++i) {
    const Eigen::Matrix3d R = i < m.dof() ? ws.R_WF[i] : ws.R_WT;
    const Eigen::Vector3d o = i < m.dof() ? ws.p_WF[i] : ws.p_WT;
    for (int k = 0; k < 3; ++k)
      segment(o, o + len * R.col(k), i == 0 ? axis_label[k] : "", axis_colour[k], false);
    if (i < m.dof())  // the joint axis: z of the body frame, both ways through the joint
      segment(o - 1.5 * len * R.col(2), o + 1.5 * len * R.col(2), i == 0 ? "joint axes" : "",
              Rgb{120, 120, 120}, true);
  }
  equalScale(p);
  return p;
}

}  // namespace

Eigen::VectorXd zeroPose(const Model& m) {
  Eigen::VectorXd q(m.dof());
  for (int i = 0; i < m.dof(); ++i)
    q[i] = std::clamp(0.0, m.joints[i].limits.q_min, m.joints[i].limits.q_max);
  return q;
}

PlotSpec armPlot(const Model& m, const Eigen::VectorXd& q, const std::string& title) {
  KinematicsWorkspace ws(m);
  forwardKinematics(m, ws, q);
  double size = (ws.p_WT - m.T_WB.translation()).norm();
  for (int i = 0; i < m.dof(); ++i)
    size = std::max(size, (ws.p_WF[i] - m.T_WB.translation()).norm());
  const double len = kFrameLengthShare * std::max(size, 0.1);
  PlotSpec spec;
  spec.title = title;
  spec.x_label = "x [m] (world)";
  spec.panels = {view(m, ws, 0, 2, "side view (x-z)", len),
                 view(m, ws, 0, 1, "top view (x-y)", len)};
  spec.panel_height = kPanelHeight_px;
  return spec;
}

Drawing drawArm(const Model& m, const Eigen::VectorXd& q, const std::string& title, Format format) {
  return plot(armPlot(m, q, title), format);
}

std::string zeroPoseSvg(const Model& m) {
  return drawArm(m, zeroPose(m), m.name + " at q = 0").svg;
}

std::string zeroPoseFileName(const std::string& design) { return "arm_" + design + ".svg"; }

Document zeroPoseFigure(const std::string& design, const std::string& rel) {
  return Document().figures(
      {{design + " at q = 0", rel}},
      "`" + design +
          "` at its zero pose (each joint's zero clamped into its limits), side view (x-z) and top "
          "view (x-y) in world metres: the links through the base, the joint frames and the TCP; "
          "each frame's x, y, z axes in red, green, blue; the joint axes dashed.");
}

std::string zeroPoseFigureMd(const std::string& design, const std::string& rel) {
  return toMarkdown(zeroPoseFigure(design, rel));
}

}  // namespace armstudy::report
