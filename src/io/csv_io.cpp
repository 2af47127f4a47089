#include "io/csv_io.hpp"

#include <charconv>
#include <cmath>
#include <regex>
#include <set>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "io/units.hpp"

namespace armstudy::io {
namespace {

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> splitCells(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(
        trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

bool skippable(const std::string& line) {
  const std::string t = trim(line);
  return t.empty() || t[0] == '#';
}

}  // namespace

int CsvTable::index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return static_cast<int>(i);
  return -1;
}

const std::vector<double>& CsvTable::column(const std::string& name) const {
  const int i = index(name);
  ARMSTUDY_CHECK(i >= 0, "CSV column '" + name + "' was not read (check has() first)");
  return values[i];
}

std::vector<CsvLine> splitCsvLines(const std::string& text) {
  std::vector<CsvLine> out;
  int line_no = 0;
  for (std::size_t pos = 0; pos <= text.size();) {
    const std::size_t nl = text.find('\n', pos);
    const std::string line =
        text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
    ++line_no;
    if (!skippable(line)) out.push_back({line_no, splitCells(line)});
    if (nl == std::string::npos) break;
    pos = nl + 1;
  }
  return out;
}

CsvTable parseCsv(const std::string& text, const std::string& file, const CsvSchema& schema) {
  CsvTable t;
  t.file = file;
  const std::vector<CsvLine> lines = splitCsvLines(text);
  if (lines.empty())
    throw InputError(file, 0, "", "the CSV file is empty (expected a header line)");
  const int header_line = lines[0].line;
  const std::vector<std::string>& header = lines[0].cells;
  std::set<std::string> seen;
  for (const std::string& h : header) {
    if (h.empty()) throw InputError(file, header_line, "", "empty column name in the header");
    if (!seen.insert(h).second)
      throw InputError(file, header_line, h, "duplicate column '" + h + "'");
  }
  std::set<std::string> wanted(schema.required.begin(), schema.required.end());
  wanted.insert(schema.optional.begin(), schema.optional.end());
  std::string missing;
  for (const std::string& r : schema.required)
    if (!seen.count(r)) {
      missing += missing.empty() ? "'" : ", '";
      missing += r + "'";
    }
  if (!missing.empty())
    throw InputError(
        file, header_line, "", "missing required column(s) " + missing + " (header has: " + [&] {
          std::string s;
          for (const auto& h : header) {
            s += s.empty() ? "" : ",";
            s += h;
          }
          return s;
        }() + ")");
  std::vector<int> header_to_column(header.size(), -1);
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (wanted.count(header[i])) {
      header_to_column[i] = static_cast<int>(t.columns.size());
      t.columns.push_back(header[i]);
    } else {
      t.extra_columns.push_back(header[i]);
    }
  }
  t.values.resize(t.columns.size());
  for (std::size_t li = 1; li < lines.size(); ++li) {
    const int line_no = lines[li].line;
    const std::vector<std::string>& cells = lines[li].cells;
    if (cells.size() != header.size())
      throw InputError(file, line_no, "",
                       "row has " + std::to_string(cells.size()) + " cells, the header has " +
                           std::to_string(header.size()));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (header_to_column[i] < 0) continue;
      const std::string& c = cells[i];
      double v = 0;
      const char* b = c.data();
      const char* e = c.data() + c.size();
      if (!c.empty() && *b == '+') ++b;
      const auto res = std::from_chars(b, e, v);
      if (c.empty() || res.ec != std::errc() || res.ptr != e)
        throw InputError(file, line_no, header[i], "cell '" + c + "' is not a number");
      if (!std::isfinite(v))
        throw InputError(file, line_no, header[i], "cell '" + c + "' is not finite (NaN or Inf)");
      if (const std::string bad = implausible(v, nullptr); !bad.empty())
        throw InputError(file, line_no, header[i], bad);
      t.values[header_to_column[i]].push_back(v);
    }
    t.row_lines.push_back(line_no);
  }
  if (t.row_lines.empty())
    throw InputError(file, header_line, "", "the CSV file has a header but no data rows");
  return t;
}

std::vector<std::string> CsvTable::extraColumnWarnings(const std::string& joint_column,
                                                       const std::string& design, int dof) const {
  const std::regex joint(joint_column.empty() ? "$^" : joint_column);
  std::vector<std::string> warnings;
  for (const std::string& x : extra_columns) {
    std::smatch mm;
    if (!joint_column.empty() && std::regex_match(x, mm, joint))
      throw InputError(file, 1, x,
                       "column '" + x + "' names joint " + mm[mm.size() - 1].str() +
                           " but design '" + design + "' has only " + std::to_string(dof) +
                           " joints");
    warnings.push_back(file + ": extra column '" + x + "' is not used");
  }
  return warnings;
}

CsvTable readCsv(const std::string& path, const CsvSchema& schema) {
  return parseCsv(readFileOrThrow(path), path, schema);
}

std::string formatCsv(const std::vector<std::string>& header,
                      const std::vector<std::vector<double>>& columns) {
  ARMSTUDY_CHECK(header.size() == columns.size(), "one header name per column");
  std::string out;
  for (std::size_t i = 0; i < header.size(); ++i) {
    out += i ? "," : "";
    out += header[i];
  }
  out += "\n";
  const std::size_t n = columns.empty() ? 0 : columns[0].size();
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      ARMSTUDY_CHECK(columns[i].size() == n, "columns of equal length");
      out += i ? "," : "";
      out += formatRoundTrip(columns[i][r]);
    }
    out += "\n";
  }
  return out;
}

}  // namespace armstudy::io
