#include "study/regression.hpp"

#include <fnmatch.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>

#include "common/enum_names.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"

namespace armstudy {

using nlohmann::ordered_json;

const ToleranceRule& RegressionSpec::ruleFor(const std::string& metric) const {
  for (const auto& r : rules)
    if (::fnmatch(r.metric.c_str(), metric.c_str(), 0) == 0) return r;
  return fallback;
}

constexpr const char* kVerdictNames[] = {"ok", "MOVED", "MISSING", "NEW"};
const char* toString(Verdict v) { return enumName(v, kVerdictNames); }

static std::string flagsToString(const std::vector<std::uint8_t>& f) {
  std::string s(f.size(), '0');
  for (std::size_t i = 0; i < f.size(); ++i) s[i] = f[i] ? '1' : '0';
  return s;
}

std::string baselineToJson(const Baseline& b) {
  ordered_json j;
  j["format"] = "armstudy-baseline";
  j["format_version"] = b.format_version;
  j["study"] = b.study;
  j["armstudy_version"] = b.armstudy_version;
  j["git_revision"] = b.git_revision;
  ordered_json s = ordered_json::object();
  for (const auto& [k, v] : b.metrics.scalars) s[k] = v;
  j["scalars"] = s;
  ordered_json f = ordered_json::object();
  for (const auto& [k, v] : b.metrics.flags) f[k] = flagsToString(v);
  j["flags"] = f;
  return j.dump(2) + "\n";
}

Baseline parseBaseline(const std::string& text, const std::string& file,
                       const std::string& expected_study) {
  ordered_json j;
  try {
    j = ordered_json::parse(text);
  } catch (const std::exception& e) {
    throw InputError(file, 0, "", std::string("baseline is not valid JSON: ") + e.what());
  }
  // A text field ("" when absent); another JSON type is an input error naming the key
  // (for example `"format": {...}`), never an escaping JSON type error.
  auto stringField = [&](const char* key) {
    if (!j.contains(key)) return std::string();
    if (!j[key].is_string()) throw InputError(file, 0, key, "expected a string");
    return j[key].get<std::string>();
  };
  if (!j.is_object() || stringField("format") != "armstudy-baseline")
    throw InputError(file, 0, "format", "not an armstudy baseline file");
  Baseline b;
  if (!j.contains("format_version") || !j["format_version"].is_number_integer())
    throw InputError(file, 0, "format_version", "missing format version");
  b.format_version = j["format_version"].get<int>();
  if (b.format_version != kBaselineFormatVersion)
    throw InputError(file, 0, "format_version",
                     "unknown baseline format version " + std::to_string(b.format_version) +
                         " (this armstudy reads version " + std::to_string(kBaselineFormatVersion) +
                         "); re-record it with `armstudy baseline`");
  b.study = stringField("study");
  if (b.study != expected_study)
    throw InputError(file, 0, "study",
                     "baseline belongs to study '" + b.study + "', not '" + expected_study + "'");
  b.armstudy_version = stringField("armstudy_version");
  b.git_revision = stringField("git_revision");
  try {
    for (const auto& [k, v] : j.at("scalars").items()) b.metrics.scalars[k] = v.get<double>();
    for (const auto& [k, v] : j.at("flags").items()) {
      const std::string s = v.get<std::string>();
      std::vector<std::uint8_t> f(s.size());
      for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '0' && s[i] != '1')
          throw std::runtime_error("flag string of '" + k + "' holds '" + s[i] + "'");
        f[i] = s[i] == '1';
      }
      b.metrics.flags[k] = f;
    }
  } catch (const std::exception& e) {
    throw InputError(file, 0, "scalars/flags", std::string("malformed baseline: ") + e.what());
  }
  return b;
}

CheckResult compareToBaseline(const Baseline& base, const StudyMetrics& now,
                              const RegressionSpec& spec) {
  CheckResult r;
  std::set<std::string> names;
  for (const auto& [k, v] : base.metrics.scalars) names.insert(k);
  for (const auto& [k, v] : now.scalars) names.insert(k);
  for (const auto& name : names) {
    CheckRow row;
    row.metric = name;
    const ToleranceRule& rule = spec.ruleFor(name);
    row.abs_tol = rule.abs;
    row.rel_tol = rule.rel;
    const auto b = base.metrics.scalars.find(name);
    const auto n = now.scalars.find(name);
    if (b == base.metrics.scalars.end()) {
      row.now = n->second;
      row.verdict = Verdict::New;
    } else if (n == now.scalars.end()) {
      row.baseline = b->second;
      row.verdict = Verdict::Missing;
    } else {
      row.baseline = b->second;
      row.now = n->second;
      const double allowed = rule.abs + rule.rel * std::abs(row.baseline);
      const bool same_nan = std::isnan(row.baseline) && std::isnan(row.now);
      row.verdict =
          (same_nan || std::abs(row.now - row.baseline) <= allowed) ? Verdict::Pass : Verdict::Fail;
    }
    r.rows.push_back(row);
  }
  names.clear();
  for (const auto& [k, v] : base.metrics.flags) names.insert(k);
  for (const auto& [k, v] : now.flags) names.insert(k);
  for (const auto& name : names) {
    CheckRow row;
    row.metric = name;
    row.is_flags = true;
    row.flips_allowed = spec.ruleFor(name).flips;
    const auto b = base.metrics.flags.find(name);
    const auto n = now.flags.find(name);
    auto count = [](const std::vector<std::uint8_t>& f) {
      double c = 0;
      for (auto x : f) c += x;
      return c;
    };
    if (b == base.metrics.flags.end()) {
      row.now = count(n->second);
      row.verdict = Verdict::New;
    } else if (n == now.flags.end()) {
      row.baseline = count(b->second);
      row.verdict = Verdict::Missing;
    } else if (b->second.size() != n->second.size()) {
      // Entries of strings of different lengths cannot be paired: the baseline was edited or
      // recorded for another grid.
      throw InputError(spec.baseline_path, 0, "flags." + name,
                       "holds " + std::to_string(b->second.size()) +
                           " per-pose flags, the run gives " + std::to_string(n->second.size()) +
                           "; the baseline was edited or recorded for another grid: re-record it "
                           "with `armstudy baseline`");
    } else {
      row.baseline = count(b->second);
      row.now = count(n->second);
      for (std::size_t i = 0; i < b->second.size(); ++i)
        if (b->second[i] != n->second[i]) {
          ++row.flips;
          if (row.flipped.size() < 10) row.flipped.push_back(i);
        }
      row.verdict = row.flips <= row.flips_allowed ? Verdict::Pass : Verdict::Fail;
    }
    r.rows.push_back(row);
  }
  return r;
}

bool CheckResult::passed() const { return failures() == 0; }
int CheckResult::failures() const {
  int n = 0;
  for (const auto& row : rows) n += row.verdict != Verdict::Pass;
  return n;
}

std::string checkTable(const CheckResult& r, bool only_moved) {
  std::string out;
  char buf[1024];
  std::snprintf(buf, sizeof buf, "%-64s %16s %16s %22s %8s\n", "metric", "baseline", "now",
                "tolerance", "verdict");
  out += buf;
  int shown = 0;
  for (const auto& row : r.rows) {
    const bool moved = row.is_flags ? row.flips > 0 : row.baseline != row.now;
    if (only_moved && !moved && row.verdict == Verdict::Pass) continue;
    ++shown;
    const std::string tol =
        row.is_flags
            ? std::to_string(row.flips) + " flip(s) of " + std::to_string(row.flips_allowed)
            : "+/-" + formatG(row.abs_tol + row.rel_tol * std::abs(row.baseline), 3) +
                  (row.rel_tol > 0 ? " (rel)" : "");
    std::snprintf(buf, sizeof buf, "%-64s %16s %16s %22s %8s\n", row.metric.c_str(),
                  formatG(row.baseline, 9).c_str(), formatG(row.now, 9).c_str(), tol.c_str(),
                  toString(row.verdict));
    out += buf;
  }
  std::snprintf(buf, sizeof buf, "%zu metric(s) compared, %d shown, %d outside tolerance\n",
                r.rows.size(), shown, r.failures());
  out += buf;
  return out;
}

std::string checkJson(const CheckResult& r) {
  ordered_json j;
  j["passed"] = r.passed();
  j["failures"] = r.failures();
  ordered_json rows = ordered_json::array();
  for (const auto& row : r.rows) {
    ordered_json o{{"metric", row.metric},
                   {"kind", row.is_flags ? "flags" : "scalar"},
                   {"baseline", row.baseline},
                   {"now", row.now},
                   {"verdict", toString(row.verdict)}};
    if (row.is_flags) {
      o["flips"] = row.flips;
      o["flips_allowed"] = row.flips_allowed;
      o["first_flipped_indices"] = row.flipped;
    } else {
      o["abs_tolerance"] = row.abs_tol;
      o["rel_tolerance"] = row.rel_tol;
    }
    rows.push_back(o);
  }
  j["rows"] = rows;
  return j.dump(2) + "\n";
}

}  // namespace armstudy
