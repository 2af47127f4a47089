#include "tasks/task_grid.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"
#include "io/units.hpp"

namespace armstudy {

int AxisRange::count() const {
  if (!(step > 0) || !(to >= from)) return 0;
  const double n = std::floor((to - from) / step * (1.0 + defaults::kGridRangeSlack) +
                              defaults::kGridRangeSlack) + 1.0;
  return n > defaults::kMaxGridAxisValues ? 0 : static_cast<int>(n);
}

std::string AxisRange::validate() const {
  if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step)) return "range values must be finite";
  if (!(step > 0)) return "step must be positive";
  if (to < from) return "empty range: 'to' is below 'from'";
  if ((to - from) / step + 1.0 > defaults::kMaxGridAxisValues)
    return "too many values on one axis (more than " + std::to_string(defaults::kMaxGridAxisValues) + ")";
  return "";
}

TaskVector6 makeTaskVector(const Eigen::Vector3d& p_W, const Orientation& o) {
  TaskVector6 w;
  w << p_W, o.alpha, o.beta, o.gamma;
  return w;
}

long TaskGrid::points() const {
  const auto d = dims();
  return static_cast<long>(d[0]) * d[1] * d[2];
}

int TaskGrid::spatialDimension() const {
  int n = 0;
  for (int a = 0; a < 3; ++a) n += axes[a].count() > 1 ? 1 : 0;
  return n;
}

Eigen::Vector3d TaskGrid::position(long point) const {
  const auto d = dims();
  const long i = point % d[0];
  const long j = (point / d[0]) % d[1];
  const long k = point / (static_cast<long>(d[0]) * d[1]);
  return {axes[0].value(static_cast<int>(i)), axes[1].value(static_cast<int>(j)),
          axes[2].value(static_cast<int>(k))};
}

TaskVector6 TaskGrid::pose(long index) const {
  return makeTaskVector(position(pointOf(index)), orientations[orientationOf(index)]);
}

long TaskGrid::lineLength() const {
  // Axes before the first multi-valued axis have one value, so a line along it is contiguous.
  for (int a = 0; a < 3; ++a)
    if (axes[a].count() > 1) return axes[a].count();
  return 1;
}

std::string TaskGrid::validate() const {
  static const char* names[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const std::string why = axes[a].validate();
    if (!why.empty()) return std::string(names[a]) + ": " + why;
  }
  if (orientations.empty()) return "a grid needs at least one orientation";
  if (task_space.dim() == 0) return "empty task space";
  if (static_cast<double>(points()) * orientations.size() > defaults::kMaxGridPoses)
    return "grid too large (more than " + std::to_string(static_cast<long>(defaults::kMaxGridPoses)) + " poses)";
  return "";
}

// ---- CSV pose lists ----

PoseList parsePoseCsv(const std::string& text, const std::string& file_label,
                      const TaskSpace& task_space) {
  static const char* kNames[6] = {"x", "y", "z", "alpha", "beta", "gamma"};
  PoseList list;
  list.file = file_label;
  list.task_space = task_space;
  std::array<int, 6> column{-1, -1, -1, -1, -1, -1};
  std::size_t columns = 0;
  bool have_header = false;
  for (const io::CsvLine& csv_line : io::splitCsvLines(text)) {
    const int line_no = csv_line.line;
    const std::vector<std::string>& cells = csv_line.cells;
    if (!have_header) {
      columns = cells.size();
      for (std::size_t c = 0; c < cells.size(); ++c) {
        int k = -1;
        for (int n = 0; n < 6; ++n)
          if (cells[c] == kNames[n]) k = n;
        if (k < 0)
          throw InputError(file_label, line_no, cells[c],
                           "unknown column in header (expected x,y,z[,alpha,beta,gamma])");
        if (column[k] >= 0) throw InputError(file_label, line_no, cells[c], "column listed twice");
        column[k] = static_cast<int>(c);
      }
      for (int n = 0; n < 3; ++n)
        if (column[n] < 0)
          throw InputError(file_label, line_no, kNames[n], "header lacks a position column");
      const int ori = (column[3] >= 0) + (column[4] >= 0) + (column[5] >= 0);
      if (ori != 0 && ori != 3)
        throw InputError(file_label, line_no, "alpha",
                         "give all three orientation columns alpha,beta,gamma or none");
      list.has_orientation = ori == 3;
      if (task_space.hasOrientation() && !list.has_orientation)
        throw InputError(file_label, line_no, "",
                         "task space " + task_space.toString() +
                             " constrains orientation but the file has no alpha,beta,gamma columns");
      have_header = true;
      continue;
    }
    if (cells.size() != columns)
      throw InputError(file_label, line_no, "",
                       "row has " + std::to_string(cells.size()) + " fields, header has " +
                           std::to_string(columns));
    TaskVector6 w = TaskVector6::Zero();
    for (int n = 0; n < 6; ++n) {
      if (column[n] < 0) continue;
      const std::string& cell = cells[column[n]];
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || errno == ERANGE || !std::isfinite(v))
        throw InputError(file_label, line_no, kNames[n],
                         "'" + cell + "' is not a finite number (metres and radians, no units)");
      const Dimension dim = n < 3 ? Dimension::Length : Dimension::Angle;
      if (const std::string bad = implausible(v, &dim); !bad.empty()) throw InputError(file_label, line_no, kNames[n], bad);
      w[n] = v;
    }
    list.poses.push_back(w);
    list.lines.push_back(line_no);
  }
  if (!have_header) throw InputError(file_label, 1, "", "empty pose list (no header)");
  if (list.poses.empty()) {
    // The last line of the text (a final '\n' ends the last line, it does not start another).
    const int last_line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) +
                          (!text.empty() && text.back() != '\n' ? 1 : 0);
    throw InputError(file_label, last_line, "", "pose list has no poses");
  }
  return list;
}

PoseList loadPoseCsv(const std::string& path, const TaskSpace& task_space) {
  return parsePoseCsv(readFileOrThrow(path), path, task_space);
}

}  // namespace armstudy
