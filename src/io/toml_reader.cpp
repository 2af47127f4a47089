#include "io/toml_reader.hpp"

#include <cctype>
#include <cmath>

#include "common/names.hpp"
#include "io/files.hpp"

namespace armstudy::io {

namespace {
std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t nl = text.find('\n', at);
    lines.push_back(text.substr(at, nl == std::string::npos ? std::string::npos : nl - at));
    if (nl == std::string::npos) break;
    at = nl + 1;
  }
  return lines;
}

// Printable ASCII only, without quotes, brackets and surrounding blanks, at most 60 characters.
std::string cleanKey(const std::string& v) {
  std::string k;
  for (unsigned char c : v)
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\'' && c != '[' && c != ']')
      k += static_cast<char>(c);
  const std::size_t b = k.find_first_not_of(" \t"), e = k.find_last_not_of(" \t");
  k = b == std::string::npos ? std::string() : k.substr(b, e - b + 1);
  return k.size() > 60 ? k.substr(0, 60) : k;
}

// The key a TOML syntax error's line is about: the text before '=' on that line, the table header
// on it, or the text written where a key was expected; else the table the line belongs to.
std::string keyOfLine(const std::string& text, int line) {
  const std::vector<std::string> lines = linesOf(text);
  if (line < 1 || line > static_cast<int>(lines.size())) return "document";
  std::string s = lines[line - 1];
  if (const std::size_t hash = s.find('#');
      hash != std::string::npos && s.find('"') == std::string::npos)
    s.resize(hash);
  std::string key = cleanKey(s.substr(0, s.find('=')));
  for (int l = line - 1; key.empty() && l >= 1; --l) {
    const std::string& h = lines[l - 1];
    const std::size_t b = h.find_first_not_of(" \t");
    if (b != std::string::npos && h[b] == '[')
      key = cleanKey(
          h.substr(b, h.find('#') == std::string::npos ? std::string::npos : h.find('#') - b));
  }
  return key.empty() ? "document" : key;
}
}  // namespace

toml::table parseTomlText(const std::string& text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    const int line = static_cast<int>(e.source().begin.line);
    throw InputError(file, line, keyOfLine(text, line),
                     "TOML syntax error: " + std::string(e.description()));
  }
}

toml::table parseTomlFile(const std::string& path) {
  return parseTomlText(readFileOrThrow(path), path);
}

TableReader::TableReader(const toml::table& table, std::string file, std::string path)
    : table_(table), file_(std::move(file)), path_(std::move(path)) {}

int TableReader::line() const { return static_cast<int>(table_.source().begin.line); }

int TableReader::line(const std::string& key) const {
  if (const toml::node* n = table_.get(key)) return static_cast<int>(n->source().begin.line);
  return line();
}

std::string TableReader::keyPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void TableReader::forEachTable(const std::string& key,
                               const std::function<void(TableReader&)>& fn) {
  const toml::array* arr = array(key);
  if (!arr) return;
  int idx = 0;
  for (const auto& e : *arr) {
    if (!e.is_table())
      throw InputError(file_, static_cast<int>(e.source().begin.line), keyPath(key),
                       "expected [[" + keyPath(key) + "]] tables");
    TableReader r(*e.as_table(), file_, keyPath(key) + "[" + std::to_string(idx++) + "]");
    fn(r);
    r.finish();
  }
}

void TableReader::fail(const std::string& key, const std::string& message) const {
  throw InputError(file_, line(key), keyPath(key), message);
}

const toml::node& TableReader::require(const std::string& key) {
  const toml::node* n = table_.get(key);
  if (!n) throw InputError(file_, line(), keyPath(key), "missing required key");
  read_.insert(key);
  return *n;
}

// A TOML number as a double. toml++'s value<double>() is empty for an integer that a double cannot
// hold exactly (beyond 2^53; found by fuzzing the study reader), so integers are converted here.
double numberOf(const toml::node& n) {
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  return n.as_floating_point()->get();
}

double nodeQuantity(const toml::node& n, Dimension dim, const std::string& file,
                    const std::string& key) {
  const int line = static_cast<int>(n.source().begin.line);
  if (n.is_number()) {
    const double v = numberOf(n);
    if (const std::string bad = implausible(v, &dim); !bad.empty())
      throw InputError(file, line, key, bad);
    return v;
  }
  if (n.is_string()) {
    double v = 0;
    std::string err;
    if (!parseQuantity(n.as_string()->get(), dim, v, err)) throw InputError(file, line, key, err);
    if (const std::string bad = implausible(v, &dim); !bad.empty())
      throw InputError(file, line, key, bad);
    return v;
  }
  throw InputError(
      file, line, key,
      std::string("expected a number or a string with unit (a ") + toString(dim) + ")");
}

double TableReader::quantity(const std::string& key, Dimension dim) {
  return nodeQuantity(require(key), dim, file_, keyPath(key));
}
double TableReader::quantity(const std::string& key, Dimension dim, double fallback) {
  return has(key) ? quantity(key, dim) : fallback;
}

double TableReader::number(const std::string& key) {
  const toml::node& n = require(key);
  if (!n.is_number()) fail(key, "expected a number");
  const double v = numberOf(n);
  if (const std::string bad = implausible(v, nullptr); !bad.empty()) fail(key, bad);
  return v;
}
double TableReader::number(const std::string& key, double fallback) {
  return has(key) ? number(key) : fallback;
}

long long TableReader::integer(const std::string& key, long long fallback) {
  if (!has(key)) return fallback;
  const toml::node& n = require(key);
  if (!n.is_integer()) fail(key, "expected an integer");
  return n.value<long long>().value();
}

int TableReader::integerIn(const std::string& key, int fallback, int lo, int hi) {
  const long long v = integer(key, fallback);
  if (v < lo || v > hi)
    fail(key, "must be between " + std::to_string(lo) + " and " + std::to_string(hi));
  return static_cast<int>(v);
}

std::uint64_t TableReader::seed(const std::string& key, std::uint64_t fallback) {
  const long long v = integer(key, static_cast<long long>(fallback));
  if (v < 0) fail(key, "seed must not be negative");
  return static_cast<std::uint64_t>(v);
}

std::string TableReader::string(const std::string& key) {
  const toml::node& n = require(key);
  if (!n.is_string()) fail(key, "expected a string");
  return n.as_string()->get();
}
std::string TableReader::string(const std::string& key, const std::string& fallback) {
  return has(key) ? string(key) : fallback;
}

std::string TableReader::name(const std::string& key, const std::string& what,
                              const std::string& punctuation, const std::string& rule) {
  std::string s = string(key);
  if (s.empty()) fail(key, what + " name is empty");
  if (!isPlainName(s, punctuation)) fail(key, rule);
  return s;
}

TableReader TableReader::requiredTable(const std::string& key, const std::string& why) {
  const toml::table* t = table(key);
  if (!t)
    throw InputError(file_, 1, keyPath(key), "missing required table [" + keyPath(key) + "]" + why);
  return TableReader(*t, file_, keyPath(key));
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  if (!has(key)) return fallback;
  const toml::node& n = require(key);
  if (!n.is_boolean()) fail(key, "expected true or false");
  return n.as_boolean()->get();
}

std::vector<std::string> TableReader::stringArray(const std::string& key) {
  std::vector<std::string> out;
  if (!has(key)) return out;
  const toml::node& n = require(key);
  if (!n.is_array()) fail(key, "expected an array of strings");
  for (const auto& e : *n.as_array()) {
    if (!e.is_string()) fail(key, "expected an array of strings");
    out.push_back(e.as_string()->get());
  }
  return out;
}

std::vector<double> TableReader::numberArray(const std::string& key) {
  std::vector<double> out;
  const toml::node& n = require(key);
  if (!n.is_array()) fail(key, "expected an array of numbers");
  for (const auto& e : *n.as_array()) {
    if (!e.is_number()) fail(key, "expected an array of numbers");
    const double v = numberOf(e);
    if (const std::string bad = implausible(v, nullptr); !bad.empty()) fail(key, bad);
    out.push_back(v);
  }
  return out;
}

const toml::table* TableReader::table(const std::string& key) {
  if (!has(key)) return nullptr;
  const toml::node& n = require(key);
  if (!n.is_table()) fail(key, "expected a table");
  return n.as_table();
}

const toml::array* TableReader::array(const std::string& key) {
  if (!has(key)) return nullptr;
  const toml::node& n = require(key);
  if (!n.is_array()) fail(key, "expected an array");
  return n.as_array();
}

const toml::node* TableReader::node(const std::string& key) {
  if (!has(key)) return nullptr;
  return &require(key);
}

void TableReader::finish() const {
  for (auto&& [k, v] : table_) {
    const std::string key(k.str());
    if (!read_.count(key))
      throw InputError(file_, static_cast<int>(v.source().begin.line), keyPath(key), "unknown key");
  }
}

}  // namespace armstudy::io
