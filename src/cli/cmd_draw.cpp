// `armstudy draw`: the arm at a joint vector as an SVG (side and top view), with its body frames
// and joint axes (report/arm_drawing.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/design_options.hpp"
#include "common/angles.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "report/arm_drawing.hpp"

namespace armstudy::cli {

namespace {

// The joint vector of --q (degrees with --deg), or the zero pose (q = 0 clamped into the limits).
Eigen::VectorXd jointVector(const Model& m, const std::vector<double>& given, bool deg) {
  if (given.empty()) return report::zeroPose(m);
  if (static_cast<int>(given.size()) != m.dof())
    throw InputError("--q", 0, "q",
                     "got " + std::to_string(given.size()) + " joint values, design '" + m.name +
                         "' has " + std::to_string(m.dof()) + " joints");
  Eigen::VectorXd q(m.dof());
  for (int i = 0; i < m.dof(); ++i)
    q[i] = given[i] * (deg && m.joints[i].type == JointType::Revolute ? kDegToRad : 1.0);
  return q;
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
    checkOutputPath(a->out);
    UrdfOptions uo = a->src.urdf();
    uo.collision = false;
    const Model m = loadAnyDesign(a->path, uo);
    const Eigen::VectorXd q = jointVector(m, a->q, a->deg);
    const std::string title = m.name + (a->q.empty() ? " at q = 0" : " at the given q");
    const bool png = a->out.size() > 4 && a->out.substr(a->out.size() - 4) == ".png";
    const report::Drawing d =
        report::drawArm(m, q, title, png ? report::Format::svg_and_png : report::Format::svg);
    writeFileAtomic(a->out, png ? d.png : d.svg);
    std::printf("wrote %s (%s, %d joints)\n", a->out.c_str(), m.name.c_str(), m.dof());
    return 0;
  });
}

}  // namespace armstudy::cli
