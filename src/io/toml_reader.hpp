#pragma once
// Internal to src/io: strict reading of one TOML table. Every key read is marked; finish() turns
// any key that was not read into an error ("unknown key"), so typos never pass silently.
// Errors are InputError with file, line and the dotted key path.
#include <toml++/toml.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "io/units.hpp"

namespace armstudy::io {

// Parses TOML text read from `file`; a syntax error becomes an InputError with the file, the line
// and the key (or table header) written on that line.
toml::table parseTomlText(const std::string& text, const std::string& file);
// Reads (readFileOrThrow: regular files of bounded size only) and parses a TOML file.
toml::table parseTomlFile(const std::string& path);

class TableReader {
 public:
  TableReader(const toml::table& table, std::string file, std::string path);

  bool has(const std::string& key) const { return table_.contains(key); }
  int line() const;                        // line where this table starts
  int line(const std::string& key) const;  // line of a key (or of the table when absent)
  std::string keyPath(const std::string& key) const;
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }

  // A number (SI) or a string expression with unit, checked against `dim`.
  double quantity(const std::string& key, Dimension dim);
  double quantity(const std::string& key, Dimension dim, double fallback);
  // A plain finite number (no unit allowed).
  double number(const std::string& key);
  double number(const std::string& key, double fallback);
  long long integer(const std::string& key, long long fallback);
  // An integer within [lo, hi] (else an input error naming the key and the range).
  int integerIn(const std::string& key, int fallback, int lo, int hi);
  // A non-negative integer seed.
  std::uint64_t seed(const std::string& key, std::uint64_t fallback);
  std::string string(const std::string& key);
  std::string string(const std::string& key, const std::string& fallback);
  // A name that names files: not empty (else "<what> name is empty"), of letters, digits and the
  // characters of `punctuation` only (else `rule`).
  std::string name(const std::string& key, const std::string& what, const std::string& punctuation,
                   const std::string& rule);
  bool boolean(const std::string& key, bool fallback);
  std::vector<std::string> stringArray(const std::string& key);
  std::vector<double> numberArray(const std::string& key);
  const toml::table* table(const std::string& key);  // nullptr when absent
  // A reader of the table `key`, which must be present ("missing required table [key]<why>").
  TableReader requiredTable(const std::string& key, const std::string& why = "");
  const toml::array* array(const std::string& key);  // nullptr when absent
  // Calls fn with a reader of each table of the array of tables `key` (path key[i]; none when
  // absent), then finishes that reader. An element that is not a table is an input error.
  void forEachTable(const std::string& key, const std::function<void(TableReader&)>& fn);
  const toml::node* node(const std::string& key);  // raw, marks the key as read
  void markRead(const std::string& key) { read_.insert(key); }

  // Throws for every key present but never read.
  void finish() const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  const toml::node& require(const std::string& key);
  const toml::table& table_;
  std::string file_;
  std::string path_;
  std::set<std::string> read_;
};

// A quantity from an arbitrary node (number or string with unit).
double nodeQuantity(const toml::node& n, Dimension dim, const std::string& file,
                    const std::string& key);

}  // namespace armstudy::io
