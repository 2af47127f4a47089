// The arm drawing against a closed-form arm: the links pass through the frames worked out by hand,
// a joint whose zero lies outside its limits is drawn at its nearer limit, and each joint axis is
// drawn along that joint's axis.
#include "report/arm_drawing.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "io/design_io.hpp"

using namespace armstudy;

namespace {

constexpr double kCoordinateTolerance = 1e-12;  // m, sums and products of a few lengths

// Three revolute joints about z, one above the other's frame along x; j2's range [0.2, 1] rad
// excludes 0, so its zero pose is 0.2 rad.
const char* kPlanarArm = R"(
[design]
name = "planar3"
[[joint]]
name = "j1"
type = "revolute"
x = 0
y = 0
z = 0.5
alpha = 0
beta = 0
gamma = 0
min = -1
max = 1
[[joint]]
name = "j2"
type = "revolute"
x = 0.3
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = 0.2
max = 1
[[joint]]
name = "j3"
type = "revolute"
x = 0.2
y = 0
z = 0
alpha = 0
beta = 0
gamma = 0
min = -1
max = 1
[tcp]
x = 0.1
)";

const report::PlotSeries& seriesLabelled(const report::PlotPanel& p, const std::string& label) {
  for (const auto& s : p.series)
    if (s.label == label) return s;
  FAIL("no series labelled '" << label << "' in panel '" << p.title << "'");
  return p.series.front();
}

}  // namespace

TEST_CASE("Arm drawing: the links of a closed-form arm at its zero pose, a joint at its limit",
          "[report][arm_drawing]") {
  const Model m = parseDesign(kPlanarArm, "planar3.toml");
  const Eigen::VectorXd q = report::zeroPose(m);
  REQUIRE(q.size() == 3);
  CHECK(q[0] == 0.0);
  CHECK(q[1] == 0.2);  // the nearer limit of [0.2, 1]
  CHECK(q[2] == 0.0);
  // By hand: F1 at (0, 0, 0.5); F2 0.3 further along x, turned by 0.2 about z; F3 and the TCP
  // 0.2 and 0.3 from F2 along F2's x axis.
  const double c = std::cos(0.2), s = std::sin(0.2);
  const double xs[5] = {0, 0, 0.3, 0.3 + 0.2 * c, 0.3 + 0.3 * c};
  const double ys[5] = {0, 0, 0, 0.2 * s, 0.3 * s};
  const double zs[5] = {0, 0.5, 0.5, 0.5, 0.5};
  const report::PlotSpec spec = report::armPlot(m, q, "planar3 at q = 0");
  REQUIRE(spec.panels.size() == 2);
  const report::PlotSeries& side =
      seriesLabelled(spec.panels[0], "links (base, joint frames, TCP)");
  const report::PlotSeries& top = seriesLabelled(spec.panels[1], "links (base, joint frames, TCP)");
  REQUIRE(side.x.size() == 5);
  REQUIRE(top.x.size() == 5);
  for (int k = 0; k < 5; ++k) {
    INFO("point " << k);
    CHECK(side.x[k] == Approx(xs[k]).margin(kCoordinateTolerance));
    CHECK(side.y[k] == Approx(zs[k]).margin(kCoordinateTolerance));
    CHECK(top.x[k] == Approx(xs[k]).margin(kCoordinateTolerance));
    CHECK(top.y[k] == Approx(ys[k]).margin(kCoordinateTolerance));
  }
  // Every joint axis is world z: vertical in the side view through its joint, a point from above.
  const report::PlotSeries& axis_side = seriesLabelled(spec.panels[0], "joint axes");
  const report::PlotSeries& axis_top = seriesLabelled(spec.panels[1], "joint axes");
  CHECK(axis_side.dashed);
  CHECK(axis_side.x[0] == Approx(axis_side.x[1]).margin(kCoordinateTolerance));
  CHECK(axis_side.y[1] - axis_side.y[0] > 0.01);
  CHECK(axis_top.x[0] == Approx(axis_top.x[1]).margin(kCoordinateTolerance));
  CHECK(axis_top.y[0] == Approx(axis_top.y[1]).margin(kCoordinateTolerance));
  // The study reports' drawing is this figure, titled at q = 0.
  CHECK(report::zeroPoseSvg(m) == report::plot(spec).svg);
}
