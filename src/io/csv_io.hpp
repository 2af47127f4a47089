#pragma once
// Strict reading of measurement CSV files (docs/calibration.md, "Measurement data").
//
// Format: a header line of unique column names, then one row per line, cells separated by ','.
// Blank lines and lines starting with '#' are skipped. Every cell of a column the caller asks for
// (required or optional) must be a finite number: a non-numeric cell, NaN or Inf is an InputError
// naming the file, the line and the column. A missing required column is an InputError naming it.
// Columns the caller did not ask for are allowed, not parsed, and listed in `extra_columns` so
// the caller can report them.
#include <string>
#include <vector>

namespace armstudy::io {

// The tokenizer under every CSV reader of the engine: the text split at '\n' into lines, each line
// into cells at ',', every cell trimmed of spaces, tabs and '\r'. Blank lines and lines starting
// with '#' are skipped. No checks on the cells (the readers check them with their own messages).
struct CsvLine {
  int line = 0;  // 1-based line in the text
  std::vector<std::string> cells;
};
std::vector<CsvLine> splitCsvLines(const std::string& text);

struct CsvSchema {
  std::vector<std::string> required;
  std::vector<std::string> optional;
};

struct CsvTable {
  std::string file;
  std::vector<std::string> columns;         // the schema columns present, in header order
  std::vector<std::vector<double>> values;  // values[column][row]
  std::vector<int> row_lines;               // 1-based line of each data row in the file
  std::vector<std::string> extra_columns;   // header columns outside the schema

  int rows() const { return static_cast<int>(row_lines.size()); }
  bool has(const std::string& name) const { return index(name) >= 0; }
  int index(const std::string& name) const;  // -1 when absent
  // The values of a schema column; precondition: has(name).
  const std::vector<double>& column(const std::string& name) const;
  // The extra columns as warnings ("<file>: extra column 'x' is not used"). A column matching
  // `joint_column` (a regular expression whose last group is a joint number, e.g. "q([0-9]+)")
  // throws InputError instead: it names a joint that the design `design` (`dof` joints) lacks.
  std::vector<std::string> extraColumnWarnings(const std::string& joint_column = "",
                                               const std::string& design = "", int dof = 0) const;
};

CsvTable parseCsv(const std::string& text, const std::string& file_label, const CsvSchema& schema);
CsvTable readCsv(const std::string& path, const CsvSchema& schema);

// Writes a table of numbers with a header (17 significant digits, round-trips exactly).
std::string formatCsv(const std::vector<std::string>& header,
                      const std::vector<std::vector<double>>& columns);

}  // namespace armstudy::io
