// `armstudy draw`: the arm at a joint vector as an SVG (side and top view), with its body frames
// and joint axes, drawn by the one plotting module (report/plot.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/design_options.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "kinematics/kinematics.hpp"
#include "report/plot.hpp"

namespace armstudy::cli {

namespace {

constexpr double kFrameLengthShare =
    0.08;                                // frame axes and joint axes: this share of the arm's size
constexpr double kPanelHeight_px = 400;  // about the plot area's width: equal scale on both axes

// The joint vector of --q (degrees with --deg), or q = 0 clamped into the limits.
Eigen::VectorXd jointVector(const Model& m, const std::vector<double>& given, bool deg) {
  Eigen::VectorXd q(m.dof());
  if (!given.empty() && static_cast<int>(given.size()) != m.dof())
    throw InputError("--q", 0, "q",
                     "got " + std::to_string(given.size()) + " joint values, design '" + m.name +
                         "' has " + std::to_string(m.dof()) + " joints");
  for (int i = 0; i < m.dof(); ++i) {
    const auto& L = m.joints[i].limits;
    q[i] = given.empty() ? std::clamp(0.0, L.q_min, L.q_max) : given[i];
    if (deg && !given.empty() && m.joints[i].type == JointType::Revolute) q[i] *= M_PI / 180.0;
  }
  return q;
}

// An invisible series that gives both axes of the panel the same span (equal scale in a square
// panel), centred on what the panel shows.
void equalScale(report::PlotPanel& p) {
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& s : p.series)
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      lo[0] = std::min(lo[0], s.x[k]), hi[0] = std::max(hi[0], s.x[k]);
      lo[1] = std::min(lo[1], s.y[k]), hi[1] = std::max(hi[1], s.y[k]);
    }
  const double half = 0.5 * std::max(hi[0] - lo[0], hi[1] - lo[1]);
  report::PlotSeries box;
  box.lines = false;
  for (int c = 0; c < 2; ++c) {
    const double mx = 0.5 * (lo[0] + hi[0]), my = 0.5 * (lo[1] + hi[1]);
    box.x.push_back(mx + (c ? half : -half));
    box.y.push_back(my + (c ? half : -half));
  }
  p.series.push_back(box);
}

// One view (a, b: the world axes drawn to the right and upwards) of the arm posed in `ws`.
report::PlotPanel view(const Model& m, const KinematicsWorkspace& ws, int a, int b,
                       const char* title, double len) {
  report::PlotPanel p;
  p.title = title;
  p.y_label = std::string(b == 2 ? "z" : "y") + " [m]";
  auto segment = [&](const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const std::string& label,
                     report::Rgb colour, bool dashed) {
    report::PlotSeries s;
    s.label = label;
    s.x = {p0[a], p1[a]};
    s.y = {p0[b], p1[b]};
    s.colour = colour;
    s.dashed = dashed;
    p.series.push_back(s);
  };
  report::PlotSeries arm;
  arm.label = "links (base, joint frames, TCP)";
  arm.markers = true;
  arm.colour = report::Rgb{40, 40, 40};
  std::vector<Eigen::Vector3d> pts{m.T_WB.translation()};
  for (int i = 0; i < m.dof(); ++i) pts.push_back(ws.p_WF[i]);
  pts.push_back(ws.p_WT);
  for (const auto& pt : pts) arm.x.push_back(pt[a]), arm.y.push_back(pt[b]);
  p.series.push_back(arm);
  const report::Rgb axis_colour[3] = {{214, 39, 40}, {44, 160, 44}, {31, 119, 180}};
  const char* axis_label[3] = {"frame x", "frame y", "frame z"};
  for (int i = 0; i <= m.dof(); ++i) {
    const Eigen::Matrix3d R = i < m.dof() ? ws.R_WF[i] : ws.R_WT;
    const Eigen::Vector3d o = i < m.dof() ? ws.p_WF[i] : ws.p_WT;
    for (int k = 0; k < 3; ++k)
      segment(o, o + len * R.col(k), i == 0 ? axis_label[k] : "", axis_colour[k], false);
    if (i < m.dof())  // the joint axis: z of the body frame, both ways through the joint
      segment(o - 1.5 * len * R.col(2), o + 1.5 * len * R.col(2), i == 0 ? "joint axes" : "",
              report::Rgb{120, 120, 120}, true);
  }
  equalScale(p);
  return p;
}

}  // namespace

void addDrawCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string path, out;
    std::vector<double> q;
    bool deg = false;
    DesignSourceOptions src;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("design", a->path, "Design file (TOML or URDF)")->required();
  addDesignSourceOptions(cmd, a->src);
  cmd->add_option("--q", a->q, "Joint values, comma-separated (default: 0 clamped into the limits)")
      ->delimiter(',');
  cmd->add_flag("--deg", a->deg, "Revolute joint values in degrees");
  cmd->add_option("--out", a->out, "The file to write: arm.svg (or arm.png)")->required();
  setAction(cmd, action, [a] {
    UrdfOptions uo = a->src.urdf();
    uo.collision = false;
    const Model m = loadAnyDesign(a->path, uo);
    const Eigen::VectorXd q = jointVector(m, a->q, a->deg);
    KinematicsWorkspace ws(m);
    forwardKinematics(m, ws, q);
    double size = (ws.p_WT - m.T_WB.translation()).norm();
    for (int i = 0; i < m.dof(); ++i)
      size = std::max(size, (ws.p_WF[i] - m.T_WB.translation()).norm());
    const double len = kFrameLengthShare * std::max(size, 0.1);
    report::PlotSpec spec;
    spec.title = m.name + (a->q.empty() ? " at q = 0" : " at the given q");
    spec.x_label = "x [m] (world)";
    spec.panels = {view(m, ws, 0, 2, "side view (x-z)", len),
                   view(m, ws, 0, 1, "top view (x-y)", len)};
    spec.panel_height = kPanelHeight_px;
    const bool png = a->out.size() > 4 && a->out.substr(a->out.size() - 4) == ".png";
    const report::Drawing d =
        report::plot(spec, png ? report::Format::svg_and_png : report::Format::svg);
    writeFileAtomic(a->out, png ? d.png : d.svg);
    std::printf("wrote %s (%s, %d joints)\n", a->out.c_str(), m.name.c_str(), m.dof());
    return 0;
  });
}

}  // namespace armstudy::cli
