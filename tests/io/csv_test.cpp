// Strict CSV reader: every bad input names file, line and column.
#include <catch2/catch.hpp>

#include "common/errors.hpp"
#include "io/csv_io.hpp"

using namespace armstudy;
using namespace armstudy::io;

namespace {
const CsvSchema kSchema{{"speed", "current"}, {"temperature"}};

InputError parseError(const std::string& text) {
  try {
    parseCsv(text, "bed.csv", kSchema);
  } catch (const InputError& e) {
    return e;
  }
  FAIL("expected an InputError");
  return InputError("", 0, "", "");
}
}  // namespace

TEST_CASE(
    "csv: columns by name / extra columns reported / comments / blank lines and CRLF skipped") {
  const CsvTable t =
      parseCsv("# test bed\nnote,current,speed\r\nx,1.5,-10\n\n+2,2.5e-1,3\n", "bed.csv", kSchema);
  CHECK(t.rows() == 2);
  CHECK(t.column("speed") == std::vector<double>{-10, 3});
  CHECK(t.column("current") == std::vector<double>{1.5, 0.25});
  CHECK_FALSE(t.has("temperature"));
  CHECK(t.extra_columns == std::vector<std::string>{"note"});  // not parsed: "x" is fine there
  CHECK(t.row_lines == std::vector<int>{3, 5});
}

TEST_CASE("csv: missing required column is named") {
  const InputError e = parseError("speed,temperature\n1,2\n");
  CHECK(std::string(e.what()).find("'current'") != std::string::npos);
  CHECK(e.line() == 1);
}

TEST_CASE("csv: non-numeric / NaN and Inf cells name file / line and column") {
  const InputError a = parseError("speed,current\n1,2\n3,abc\n");
  CHECK(a.file() == "bed.csv");
  CHECK(a.line() == 3);
  CHECK(a.key() == "current");
  const InputError b = parseError("speed,current\nnan,2\n");
  CHECK(b.line() == 2);
  CHECK(b.key() == "speed");
  CHECK(std::string(b.what()).find("NaN") != std::string::npos);
  CHECK(parseError("speed,current\n1,inf\n").key() == "current");
  CHECK(parseError("speed,current\n1,\n").key() == "current");
  CHECK(parseError("speed,current\n1,2 3\n").line() == 2);
}

TEST_CASE("csv: structural errors") {
  CHECK(parseError("").line() == 0);
  CHECK(parseError("speed,current\n").line() == 1);                    // header only
  CHECK(parseError("speed,current,speed\n1,2,3\n").key() == "speed");  // duplicate column
  CHECK(parseError("speed,current\n1,2,3\n").line() == 2);             // cell count
  CHECK(parseError("speed,,current\n1,2,3\n").line() == 1);            // empty name
}

TEST_CASE("csv: formatCsv round-trips exactly") {
  const std::vector<double> s = {0.1, -1.0 / 3.0, 1e-300, 123456789.123};
  const std::vector<double> c = {2.0, 3.5, -0.0, 7e10};
  const CsvTable t = parseCsv(formatCsv({"speed", "current"}, {s, c}), "rt.csv", kSchema);
  CHECK(t.column("speed") == s);
  CHECK(t.column("current") == c);
}
