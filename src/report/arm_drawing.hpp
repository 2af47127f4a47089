#pragma once
// The arm drawn at a joint vector: a side view (x-z) and a top view (x-y) in world metres, with the
// links as a polyline through the base, the joint frames and the TCP, each body frame's axes and
// each joint axis (dashed), drawn by the one plotting module (plot.hpp). `armstudy draw` and the
// study reports (the designs at their zero pose) use it.
#include <Eigen/Core>
#include <string>

#include "model/model.hpp"
#include "report/document.hpp"
#include "report/plot.hpp"

namespace armstudy::report {

// q = 0 clamped into each joint's limits (the zero pose a design is drawn at by default).
Eigen::VectorXd zeroPose(const Model& m);

// The figure of `m` at `q` (m.dof() values, SI), titled `title`.
PlotSpec armPlot(const Model& m, const Eigen::VectorXd& q, const std::string& title);

// The figure drawn (svg; png too with Format::svg_and_png). Deterministic: the same bytes for the
// same model and q.
Drawing drawArm(const Model& m, const Eigen::VectorXd& q, const std::string& title,
                Format format = Format::svg);

// The study reports' drawing of a design: `m` at its zero pose, titled "<name> at q = 0" (SVG).
std::string zeroPoseSvg(const Model& m);
// The file name of that drawing: "arm_<name>.svg" (in a report's images folder).
std::string zeroPoseFileName(const std::string& design);
// The figure (image and caption) of that drawing at `rel` (relative to the report), and its
// Markdown.
Document zeroPoseFigure(const std::string& design, const std::string& rel);
std::string zeroPoseFigureMd(const std::string& design, const std::string& rel);

}  // namespace armstudy::report
