#include "io/pose_list_io.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/errors.hpp"
#include "io/csv_io.hpp"
#include "io/files.hpp"
#include "io/units.hpp"

namespace armstudy {

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
        throw InputError(
            file_label, line_no, "",
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
      if (const std::string bad = implausible(v, &dim); !bad.empty())
        throw InputError(file_label, line_no, kNames[n], bad);
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
