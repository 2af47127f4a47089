#include <array>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/format.hpp"
#include "report/markdown.hpp"
#include "stages/calibration/calibration_stage.hpp"

namespace armstudy::calibration {

using nlohmann::ordered_json;

namespace {

// ---------------------------------------------------------------------------------------------
// Summary <-> JSON
// ---------------------------------------------------------------------------------------------

ordered_json finite(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }
double number(const ordered_json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

}  // namespace

std::string effectWords(const std::string& key) {
  static const std::map<std::string, std::string> words{
      {"viscous", "viscous friction"},
      {"coulomb", "Coulomb friction"},
      {"stribeck", "Stribeck friction"},
      {"armature", "armature inertia"},
      {"inertia", "inertia"},
      {"link_mass", "link mass"},
      {"joint_offset", "joint offset"},
      {"link_length", "link length"},
      {"payload", "payload"},
      {"load_viscous", "load-dependent viscous friction"}};
  std::vector<std::string> parts;
  for (std::size_t a = 0;;) {
    const std::size_t b = key.find('.', a);
    parts.push_back(key.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  // A parameter named like its effect ("joint_1.viscous.viscous") is that effect.
  // So is one named like the last word of its type ("joint_offset.j3.offset").
  const auto endsWithWord = [](const std::string& a, const std::string& w) {
    return a.size() > w.size() && a.compare(a.size() - w.size() - 1, w.size() + 1, "_" + w) == 0;
  };
  if (parts.size() >= 2 &&
      (parts.back() == parts[parts.size() - 2] || endsWithWord(parts[0], parts.back())))
    parts.pop_back();
  const auto word = [&](const std::string& p) {
    const auto it = words.find(p);
    return it == words.end() ? p : it->second;
  };
  if (parts.size() == 1) return word(parts[0]);
  // "<type>.<joint>[.<axis>]" (link_mass.joint_4, link_length.j4.x) or "<joint>.<effect>"
  // (joint_1.viscous, j3.stribeck).
  std::string out;
  if (words.count(parts[0]) && !words.count(parts[1])) {
    out = parts[1] + " " + word(parts[0]);
    for (std::size_t k = 2; k < parts.size(); ++k) out += " " + parts[k];
  } else {
    out = parts[0];
    for (std::size_t k = 1; k < parts.size(); ++k) out += " " + word(parts[k]);
  }
  return out;
}

ShownUnit shownUnit(const std::string& unit) {
  if (unit == "m") return {1e3, "mm", 2};
  return {1, unit, -1};
}

std::string shown(double v, const ShownUnit& u) {
  if (!std::isfinite(v)) return "-";
  if (u.decimals < 0) return formatG(u.scale * v, 4);
  return report::fixed(u.scale * v, u.decimals);
}

std::string entrySummaryToJson(const EntrySummary& s) {
  ordered_json j;
  j["name"] = s.name;
  j["kind"] = s.kind;
  j["design"] = s.design;
  j["data"] = {{"file", s.data_file}, {"hash", s.data_hash}};
  if (!s.joint.empty()) j["drive"] = s.joint;
  j["mode"] = s.mode;
  j["unit"] = s.unit;
  j["noise_estimate"] = finite(s.noise_estimate);
  j["as_designed"] = {{"rmse", finite(s.as_designed_rmse)},
                      {"flagged_bins", s.as_designed_flagged},
                      {"bins", s.bins}};
  ordered_json ladder = ordered_json::array();
  for (const LadderStep& l : s.ladder)
    ladder.push_back({{"label", l.label},
                      {"n_params", l.n_params},
                      {"train_rmse", finite(l.train_rmse)},
                      {"heldout_rmse", finite(l.heldout_rmse)}});
  j["ladder"] = ladder;
  ordered_json cat = ordered_json::array();
  for (std::size_t i = 0; i < s.catalogue.size(); ++i)
    cat.push_back({{"effect", s.catalogue[i]}, {"significant", s.significant[i] != 0}});
  j["candidates"] = cat;
  j["added"] = s.added;
  j["verdict"] = s.verdict;
  j["rmse_before"] = finite(s.rmse_before);
  j["rmse_after"] = finite(s.rmse_after);
  ordered_json params = ordered_json::array();
  for (const FittedParameter& p : s.final_params)
    params.push_back({{"key", p.key},
                      {"value", finite(p.value)},
                      {"unit", p.unit},
                      {"ci95", {finite(p.ci_low), finite(p.ci_high)}},
                      {"at_bound", p.at_bound}});
  j["final_params"] = params;
  j["calibrated"] = {{"design", s.calibrated_design},
                     {"rmse", finite(s.calibrated_rmse)},
                     {"flagged_bins", s.calibrated_flagged}};
  j["notes"] = s.notes;
  j["warnings"] = s.warnings;
  j["files"] = s.files;
  if (!s.answers.empty()) j["answers"] = s.answers;
  if (!s.remainders.empty()) j["remainders"] = s.remainders;
  if (!s.extra_metrics.empty()) {
    ordered_json m = ordered_json::object();
    for (const auto& [k, v] : s.extra_metrics) m[k] = finite(v);
    j["identification"] = m;
  }
  return j.dump(2) + "\n";
}

EntrySummary entrySummaryFromJson(const std::string& text) {
  const ordered_json j = ordered_json::parse(text);
  EntrySummary s;
  s.name = j.at("name").get<std::string>();
  s.kind = j.at("kind").get<std::string>();
  s.design = j.at("design").get<std::string>();
  s.data_file = j.at("data").at("file").get<std::string>();
  s.data_hash = j.at("data").at("hash").get<std::string>();
  s.joint = j.value("drive", std::string());
  s.mode = j.at("mode").get<std::string>();
  s.unit = j.at("unit").get<std::string>();
  s.noise_estimate = number(j.at("noise_estimate"));
  s.as_designed_rmse = number(j.at("as_designed").at("rmse"));
  s.as_designed_flagged = j.at("as_designed").at("flagged_bins").get<int>();
  s.bins = j.at("as_designed").at("bins").get<int>();
  for (const auto& l : j.at("ladder"))
    s.ladder.push_back({l.at("label").get<std::string>(), l.at("n_params").get<int>(),
                        number(l.at("train_rmse")), number(l.at("heldout_rmse"))});
  for (const auto& c : j.at("candidates")) {
    s.catalogue.push_back(c.at("effect").get<std::string>());
    s.significant.push_back(c.at("significant").get<bool>() ? 1 : 0);
  }
  s.added = j.at("added").get<std::vector<std::string>>();
  s.verdict = j.at("verdict").get<std::string>();
  s.rmse_before = number(j.at("rmse_before"));
  s.rmse_after = number(j.at("rmse_after"));
  for (const auto& p : j.at("final_params")) {
    FittedParameter f;
    f.key = p.at("key").get<std::string>();
    f.value = number(p.at("value"));
    f.unit = p.at("unit").get<std::string>();
    f.ci_low = number(p.at("ci95").at(0));
    f.ci_high = number(p.at("ci95").at(1));
    f.at_bound = p.at("at_bound").get<bool>();
    s.final_params.push_back(f);
  }
  s.calibrated_design = j.at("calibrated").at("design").get<std::string>();
  s.calibrated_rmse = number(j.at("calibrated").at("rmse"));
  s.calibrated_flagged = j.at("calibrated").at("flagged_bins").get<int>();
  s.notes = j.at("notes").get<std::vector<std::string>>();
  s.warnings = j.at("warnings").get<std::vector<std::string>>();
  s.files = j.at("files").get<std::vector<std::string>>();
  if (j.contains("answers")) s.answers = j.at("answers").get<std::vector<std::string>>();
  if (j.contains("remainders")) s.remainders = j.at("remainders").get<std::vector<std::string>>();
  if (j.contains("identification"))
    for (const auto& [k, v] : j.at("identification").items())
      s.extra_metrics.emplace_back(k, number(v));
  return s;
}

std::string viewCloudsToJson(const std::vector<report::ViewCloud>& clouds) {
  ordered_json a = ordered_json::array();
  for (const report::ViewCloud& c : clouds) {
    ordered_json v = ordered_json::array();
    for (double x : c.value) v.push_back(finite(x));
    a.push_back({{"name", c.name},
                 {"p_W", c.p_W},
                 {"status", c.status},
                 {"status_names", c.status_names},
                 {"value", v},
                 {"unit", c.value_unit},
                 {"quantity", c.value_quantity},
                 {"point_size", c.point_size_m},
                 {"arm_W", c.arm_W},
                 {"arm_caption", c.arm_caption}});
  }
  return a.dump();
}

std::vector<report::ViewCloud> viewCloudsFromJson(const std::string& json) {
  std::vector<report::ViewCloud> out;
  for (const auto& j : ordered_json::parse(json)) {
    report::ViewCloud c;
    c.name = j.at("name").get<std::string>();
    c.p_W = j.at("p_W").get<std::vector<std::array<double, 3>>>();
    c.status = j.at("status").get<std::vector<int>>();
    c.status_names = j.at("status_names").get<std::vector<std::string>>();
    for (const auto& v : j.at("value")) c.value.push_back(number(v));
    c.value_unit = j.at("unit").get<std::string>();
    c.value_quantity = j.at("quantity").get<std::string>();
    c.point_size_m = j.at("point_size").get<double>();
    c.arm_W = j.at("arm_W").get<std::vector<std::array<double, 3>>>();
    c.arm_caption = j.at("arm_caption").get<std::string>();
    if (c.p_W.size() != c.status.size() || c.p_W.size() != c.value.size())
      throw std::runtime_error("view cloud '" + c.name + "': arrays of different lengths");
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace armstudy::calibration
