#include "stages/reach/reach_answer.hpp"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

#include "common/format.hpp"
#include "report/markdown.hpp"

// The reach stage's answer from its summary, and the dexterity comparison of design pairs.
namespace armstudy::reach_report {

using nlohmann::ordered_json;

namespace {
struct PairDexterity {
  long both = 0;
  double w[2] = {0, 0}, t[2] = {0, 0}, r[2] = {0, 0};  // means over the poses both reach
};
// +1 when every ratio b/a is above 1 (b better), -1 when every one is below, 0 otherwise.
int agreement(const std::vector<double>& ratios) {
  bool up = true, down = true;
  for (double x : ratios) {
    up &= x > 1;
    down &= x < 1;
  }
  return up ? 1 : (down ? -1 : 0);
}
}  // namespace

namespace {
// "`a` reaches the most, 95.6 % (`b` 81.8 %, `c` 0.0 %)" over one grid's or list's designs. On a
// grid, designs are level with the first when their difference in reachable poses is at most half
// the two designs' boundary poses (the reach boundary is known to within one grid spacing); the
// pairs' counts then say what each reaches alone.
std::string coverageSentence(const CoverageFacts& set, std::vector<std::string>& warnings) {
  const std::string of = " of the " + std::to_string(set.poses) + " poses of " + set.what;
  std::vector<DesignCoverage> f = set.designs;
  for (const DesignCoverage& d : f)
    if (d.reachable == 0) warnings.push_back("`" + d.design + "` reaches none" + of + ".");
  std::stable_sort(f.begin(), f.end(), [](const DesignCoverage& a, const DesignCoverage& b) {
    return a.fraction > b.fraction;
  });
  if (f.empty()) return "";
  if (f.size() == 1)
    return "`" + f[0].design + "` reaches " + report::percent(f[0].fraction) + of + ".";
  auto level = [&](const DesignCoverage& e) {
    return report::percent(e.fraction) == report::percent(f[0].fraction) ||
           2 * (f[0].reachable - e.reachable) <= f[0].boundary + e.boundary;
  };
  std::size_t k = 0;
  std::string top, rest;
  for (; k < f.size() && level(f[k]); ++k)
    top += std::string(k ? ", " : "") + "`" + f[k].design + "` " + report::percent(f[k].fraction);
  for (std::size_t j = k; j < f.size(); ++j)
    rest +=
        std::string(j > k ? ", " : "") + "`" + f[j].design + "` " + report::percent(f[j].fraction);
  std::string a;
  if (k == 1)
    a = "`" + f[0].design + "` reaches the most" + of + ", " + report::percent(f[0].fraction);
  else
    a = std::string(k == f.size() ? "Level" : "Level at the top") + of + ": " + top;
  if (k < f.size()) a += (k == 1 ? " (then " : "; then ") + rest + (k == 1 ? ")" : "");
  if (k > 1) {
    const long diff = f[0].reachable - f[k - 1].reachable;
    a += ". The difference, " + std::to_string(diff) + " poses, is inside the grid's resolution (" +
         "half the poses on the reach boundaries, where one grid spacing decides)";
    for (const PairCoverage& pr : set.pairs)
      for (std::size_t x = 0; x < k; ++x)
        for (std::size_t y = x + 1; y < k; ++y)
          if ((pr.a == f[x].design && pr.b == f[y].design) ||
              (pr.a == f[y].design && pr.b == f[x].design))
            a += "; only `" + pr.a + "` reaches " + std::to_string(pr.a_only) + ", only `" + pr.b +
                 "` " + std::to_string(pr.b_only);
  }
  return a + ".";
}
// Each design's largest reach found against its reference_reach_m: a sentence of the answer, and
// a warning when they differ by more than the grid resolves (one step).
void referenceReachAnswer(const CoverageFacts& set, std::vector<std::string>& answer,
                          std::vector<std::string>& warnings) {
  for (const ReachAgainstReference& r : set.references) {
    const std::string design = "`" + r.design + "`";
    const std::string ref_text = report::fixed(r.reference_m * 1e3, 0) + " mm";
    if (r.found_m < 0) {
      warnings.push_back(design + " reaches no pose of " + set.what +
                         ": its reach cannot be compared with the reference " + ref_text + ".");
      continue;
    }
    const double diff = r.found_m - r.reference_m;
    const std::string sign = diff >= 0 ? "+" : "";
    const std::string text =
        design + " largest reach found on " + set.what + ": " + report::fixed(r.found_m * 1e3, 0) +
        " mm against the reference " + ref_text + " (" + sign + report::fixed(diff * 1e3, 0) +
        " mm, " + sign + report::fixed(100 * diff / r.reference_m, 1) + " %; the grid resolves " +
        report::fixed(r.resolution_m * 1e3, 0) + " mm)";
    answer.push_back(text + ".");
    if (std::abs(diff) > r.resolution_m)
      warnings.push_back(text +
                         ": the difference is larger than the grid resolves; check the "
                         "reference's definition (base axis to flange or to the TCP) and "
                         "the design's tool.");
  }
}
// The pairs ranked by dexterity where both reach, "" when none is.
std::string verdictsText(const CoverageFacts& set) {
  std::string verdicts;
  for (const PairVerdict& v : set.verdicts) {
    if (v.better.empty()) continue;
    const bool a_better = v.a == v.better;
    const double ratio = a_better ? v.mean_a / v.mean_b : v.mean_b / v.mean_a;
    verdicts += std::string(verdicts.empty() ? "" : "; ") + "`" + (a_better ? v.a : v.b) + "` " +
                formatG(ratio, 3) + "x `" + (a_better ? v.b : v.a) + "` (" +
                std::to_string(v.both) + " poses)";
  }
  return verdicts;
}
}  // namespace

void reachAnswer(const ReachFacts& facts, std::vector<std::string>& answer,
                 std::vector<std::string>& warnings) {
  for (const CoverageFacts& set : facts.sets) {
    std::string a = coverageSentence(set, warnings);
    if (a.empty()) continue;
    a[0] = a[0] == '`' ? a[0] : static_cast<char>(std::toupper(static_cast<unsigned char>(a[0])));
    const std::string verdicts = verdictsText(set);
    if (!verdicts.empty())
      a += " More dexterous where both reach (manipulability of the task's rows, ranked only "
           "where its translational and rotational parts agree): " +
           verdicts + ".";
    answer.push_back(a);
    referenceReachAnswer(set, answer, warnings);
  }
  if (!facts.without_volumes.empty()) {
    std::string names;
    for (const std::string& n : facts.without_volumes)
      names += std::string(names.empty() ? "" : ", ") + "`" + n + "`";
    warnings.push_back(
        names +
        " evaluated without self-collision and obstacles (no collision volumes): their "
        "reachable shares are not comparable with the others'.");
  }
}

nlohmann::ordered_json dexterityComparison(
    const std::vector<const Model*>& models, const TaskGrid& g,
    const std::vector<PoseSweep>& sweeps,
    const std::vector<std::pair<std::size_t, std::size_t>>& pairs, int threads,
    report::Document& doc, std::vector<PairVerdict>& pair_verdicts) {
  std::vector<std::vector<ManipulabilityParts>> parts;
  for (std::size_t d = 0; d < sweeps.size(); ++d)
    parts.push_back(manipulabilityParts(*models[d], g, sweeps[d], threads));
  const bool rot = g.task_space.hasOrientation();
  ordered_json out = ordered_json::array();
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> verdicts;
  for (const auto& [a, b] : pairs) {
    PairDexterity pd;
    for (long i = 0; i < g.size(); ++i) {
      if (!(sweeps[a].reachable(i) && sweeps[b].reachable(i))) continue;
      ++pd.both;
      const std::size_t u = static_cast<std::size_t>(i);
      const std::size_t ab[2] = {a, b};
      for (int s = 0; s < 2; ++s) {
        pd.w[s] += sweeps[ab[s]].manipulability[u];
        pd.t[s] += parts[ab[s]][u].translation;
        pd.r[s] += parts[ab[s]][u].rotation;
      }
    }
    const std::string &na = sweeps[a].design, &nb = sweeps[b].design;
    ordered_json j = {{"a", na}, {"b", nb}, {"poses_both_reach", pd.both}};
    if (pd.both == 0) {
      out.push_back(j);
      continue;
    }
    for (int s = 0; s < 2; ++s) {
      pd.w[s] /= pd.both;
      pd.t[s] /= pd.both;
      pd.r[s] /= pd.both;
    }
    const double rw = pd.w[1] / pd.w[0], rt = pd.t[1] / pd.t[0], rr = rot ? pd.r[1] / pd.r[0] : rt;
    const int agree = agreement({rw, rt, rr});
    j["manipulability_mean"] = {pd.w[0], pd.w[1]};
    j["translation_mean"] = {pd.t[0], pd.t[1]};
    if (rot) j["rotation_mean"] = {pd.r[0], pd.r[1]};
    j["better"] =
        agree > 0 ? ordered_json(nb) : (agree < 0 ? ordered_json(na) : ordered_json(nullptr));
    out.push_back(j);
    pair_verdicts.push_back(
        {na, nb, agree > 0 ? nb : (agree < 0 ? na : std::string()), pd.w[0], pd.w[1], pd.both});
    auto ratio = [](double x) {
      return x >= 1 ? report::fixed(x, 2) + "x" : "1/" + report::fixed(1 / x, 2) + "x";
    };
    std::vector<std::string> row{na,
                                 nb,
                                 std::to_string(pd.both),
                                 report::fixed(pd.w[0], 3) + " / " + report::fixed(pd.w[1], 3),
                                 ratio(rw),
                                 ratio(rt)};
    if (rot) row.push_back(ratio(rr));
    rows.push_back(row);
    if (agree != 0) {
      const std::string& better = agree > 0 ? nb : na;
      const std::string& worse = agree > 0 ? na : nb;
      const double f = agree > 0 ? rw : 1 / rw;
      verdicts.push_back(
          "`" + better + "` is more dexterous than `" + worse + "` on the " +
          std::to_string(pd.both) + " poses both reach: " + report::fixed(f, 2) +
          "x the manipulability" +
          (rot ? ", and better in both its translational and rotational parts." : "."));
    } else {
      verdicts.push_back("`" + na + "` vs `" + nb + "`: no ranking; the combined value favours `" +
                         (rw > 1 ? nb : na) + "` but the translational part favours `" +
                         (rt > 1 ? nb : na) + "` and the rotational part `" + (rr > 1 ? nb : na) +
                         "` (the combined value depends on the 1 m that weighs the angular rows).");
    }
  }
  if (rows.empty()) return out;
  std::vector<std::string> header{
      "A", "B", ">poses both reach", ">manipulability A / B", ">B/A", ">B/A translation"};
  if (rot) header.push_back(">B/A rotation");
  doc.paragraph(
         "Dexterity where both reach (means over the poses both designs reach; "
         "manipulability of the rows the task constrains, " +
         std::string(rot ? "the angular rows weighed by a characteristic length of 1 m; "
                           "translation: the 3 position rows alone [m^3]; rotation: the "
                           "angular rows alone [1]"
                         : "the 3 position rows [m^3]") +
         "; a pair is ranked only when all agree):")
      .table(header, rows)
      .list(verdicts);
  return out;
}

}  // namespace armstudy::reach_report
