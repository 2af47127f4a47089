#include "stages/dexterity/dexterity_status.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "common/angles.hpp"
#include "common/format.hpp"
#include "dexterity/dexterity_audit.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"
#include "report/plot.hpp"

namespace armstudy::dexterity {

namespace {

// The statuses a stem cell can have, in the order the report lists them.
constexpr ReachStatus kCellStatuses[] = {
    ReachStatus::Reachable,     ReachStatus::ObstacleCollision,
    ReachStatus::SelfCollision, ReachStatus::JointLimits,
    ReachStatus::OutOfReach,    ReachStatus::RepresentationSingularity};

}  // namespace

bool inHalf(double gamma_rad, Half h) {
  constexpr double kSide = 1e-9;  // |cos gamma| below this: beside the stem, along the row
  switch (h) {
    case Half::Negative:
      return gamma_rad < 0;
    case Half::NonNegative:
      return gamma_rad >= 0;
    case Half::Near:
      return std::cos(gamma_rad) > kSide;
    case Half::Far:
      return std::cos(gamma_rad) < -kSide;
  }
  return false;
}

StatusCounts statusCounts(const DexterityMap& map) {
  StatusCounts c;
  const int G = map.grid.gamma_rad.count;
  for (int i = 0; i < static_cast<int>(map.cells.size()); ++i) {
    const double gamma = map.grid.gamma_rad.value(i % G);
    for (int h = 0; h < kHalves; ++h) {
      if (!inHalf(gamma, static_cast<Half>(h))) continue;
      ++c.cells[h];
      ++c.by[h][static_cast<int>(map.cells[i].status)];
    }
  }
  return c;
}

std::string mostFrequentPair(const DexterityMap& map, ReachStatus status, const Half* h) {
  const int G = map.grid.gamma_rad.count;
  std::map<int, int> n;
  for (int i = 0; i < static_cast<int>(map.cells.size()); ++i) {
    const CellResult& c = map.cells[i];
    if (h && !inHalf(map.grid.gamma_rad.value(i % G), *h)) continue;
    if (c.status == status && c.colliding_pair >= 0) ++n[c.colliding_pair];
  }
  int best = -1, count = 0;
  for (const auto& [pair, k] : n)
    if (k > count) best = pair, count = k;
  if (best < 0 || best >= static_cast<int>(map.pair_names.size())) return "";
  return map.pair_names[best];
}

std::string limitingEffect(const DexterityMap& map, const StatusCounts& c, Half h) {
  ReachStatus worst = ReachStatus::Reachable;
  int most = 0;
  for (ReachStatus s : kCellStatuses)
    if (s != ReachStatus::Reachable && c.count(h, s) > most) worst = s, most = c.count(h, s);
  if (most == 0) return "nothing";
  const std::string pair = mostFrequentPair(map, worst, &h);
  switch (worst) {
    case ReachStatus::ObstacleCollision: {
      const bool own = pair.size() >= 5 && pair.compare(pair.size() - 5, 5, ":stem") == 0;
      const bool row = pair.find(":stem_") != std::string::npos;
      return std::string(own   ? "the stem itself"
                         : row ? "neighbouring stems"
                               : "obstacles") +
             " (" + pair + ")";
    }
    case ReachStatus::SelfCollision:
      return "self-collision (" + pair + ")";
    case ReachStatus::JointLimits:
      return "joint limits";
    case ReachStatus::OutOfReach:
      return "reach";
    default:
      return toString(worst);
  }
}

std::string writeStatusMap(const DexterityMap& map, const std::string& sub, Writer& out) {
  const StatusCounts c = statusCounts(map);
  for (ReachStatus s : kCellStatuses)
    if (c.count(Half::Negative, s) + c.count(Half::NonNegative, s) ==
        static_cast<long>(map.cells.size()))
      return "100 % of the " + std::to_string(map.cells.size()) + " cells " + describe(s) +
             " (no map drawn)";
  const int G = map.grid.gamma_rad.count, Z = map.grid.z_m.count;
  const report::RasterImage cells = report::renderCellMap(G, Z, [&](int i, int j) {
    return report::categorical(static_cast<int>(map.cells[map.grid.index(i, j)].status));
  });
  const AxisRange& ga = map.grid.gamma_rad;
  const AxisRange& za = map.grid.z_m;
  report::MapFigure f;
  f.title = map.design + ": status";
  f.x = report::cellAxis("gamma [deg]", ga.min * kRadToDeg, ga.max * kRadToDeg,
                         ga.step() * kRadToDeg);
  f.y = report::cellAxis("z [m]", za.min, za.max, za.step());
  for (ReachStatus s : kCellStatuses)
    if (c.count(Half::Negative, s) + c.count(Half::NonNegative, s) > 0)
      f.legend.push_back({report::categorical(static_cast<int>(s)), describe(s)});
  const report::Drawing fig = report::mapFigure(cells, f, report::Format::svg_and_png);
  const std::string name = map.design + "_status";
  out.text(sub + "/" + name + ".svg", fig.svg);
  out.text(sub + "/" + name + ".png", fig.png);
  return "![" + map.design + ": status](" + name + ".svg)";
}

report::Document statusSection(const DexterityMap& map, const StatusCounts& c) {
  report::Document doc;
  doc.paragraph(std::string("Status of the cells (") +
                (map.collision ? "collision-aware" : "no collision model") +
                "; `status` in the .vti; near half: |gamma| < 90 deg, the robot's side of the "
                "row; far half: |gamma| > 90 deg):");
  std::vector<std::vector<std::string>> rows;
  for (ReachStatus s : kCellStatuses) {
    if (c.count(Half::Negative, s) + c.count(Half::NonNegative, s) == 0 &&
        s != ReachStatus::Reachable)
      continue;
    const std::string pair = mostFrequentPair(map, s);
    rows.push_back({toString(s)});
    for (Half h : {Half::Negative, Half::NonNegative, Half::Near, Half::Far})
      rows.back().push_back(std::to_string(c.count(h, s)) + " (" +
                            formatShare(c.count(h, s), c.total(h), 1) + ")");
    rows.back().push_back(pair.empty() ? "-" : "`" + pair + "`");
  }
  doc.table({"status", "gamma < 0", "gamma >= 0", "near half", "far half", "most frequent pair"},
            rows, report::TableRule::compact);
  const MapSearchSummary& se = map.search;
  if (se.collision_cells > 0)
    doc.paragraph("Cells still in collision after the neighbour propagation: " +
                  std::to_string(se.collision_cells) + ", " + std::to_string(se.collision_tries) +
                  " further random starts freed " + std::to_string(se.collision_freed) +
                  " of them.");
  return doc;
}

void addStatusJson(const DexterityMap& map, const StatusCounts& c, nlohmann::ordered_json& d) {
  const char* const names[kHalves] = {"gamma_negative", "gamma_non_negative", "near_half",
                                      "far_half"};
  nlohmann::ordered_json js;
  js["collision_checked"] = map.collision;
  for (int h = 0; h < kHalves; ++h) {
    nlohmann::ordered_json half = {{"cells", c.cells[h]}};
    for (ReachStatus s : kCellStatuses) half[toString(s)] = c.by[h][static_cast<int>(s)];
    half["limited_by"] = limitingEffect(map, c, static_cast<Half>(h));
    js[names[h]] = half;
  }
  nlohmann::ordered_json pairs = nlohmann::ordered_json::object();
  for (ReachStatus s : {ReachStatus::ObstacleCollision, ReachStatus::SelfCollision}) {
    const std::string p = mostFrequentPair(map, s);
    pairs[toString(s)] = p.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(p);
  }
  js["most_frequent_pair"] = pairs;
  js["checked_pairs"] = map.pair_names;
  d["status"] = js;
}

// The audit's files: writes <design>_audit.csv, sets d["audit"] and returns the report paragraph.
report::Document writeAudit(const Model& m, const DexterityOptions& options,
                            const DexterityAudit& a, const std::string& sub, Writer& out,
                            nlohmann::ordered_json& d) {
  const StemGrid& g = options.grid;
  const int G = g.gamma_rad.count;
  nlohmann::ordered_json aj;
  aj["cells"] = a.cells;
  aj["starts_per_cell"] = a.starts;
  aj["seed"] = a.seed;
  aj["both_reachable"] = a.both_reachable;
  aj["share_within_1pct"] = a.shareWithin1Percent();
  aj["share_within_5pct"] = a.both_reachable ? double(a.within_5pct) / a.both_reachable : 1.0;
  aj["reachability_contradicted"] = a.reach_contradicted;
  aj["audit_found_no_solution"] = a.audit_missed;
  aj["worst_gap"] = a.worst_gap;
  nlohmann::ordered_json verdicts = nlohmann::ordered_json::object();
  for (int k = 0; k < kReachStatusCount; ++k)
    if (a.verdicts[k] > 0)
      verdicts[toString(static_cast<ReachStatus>(k))] = {{"cells", a.verdicts[k]},
                                                         {"contradicted", a.contradicted[k]}};
  aj["verdicts"] = verdicts;
  if (a.worst_index >= 0)
    aj["worst_at"] = {{"gamma_rad", g.gamma_rad.value(a.worst_index % G)},
                      {"z_m", g.z_m.value(a.worst_index / G)}};
  d["audit"] = aj;
  std::ostringstream csv;
  csv << "cell,gamma_rad,z_m,map_status,map_reachable,audit_reachable,H_map,H_audit,gap,"
         "manipulability_map,"
         "manipulability_audit,audit_solutions,audit_on_pose\n";
  for (const AuditCell& r : a.rows)
    csv << r.index << "," << formatRoundTrip(r.gamma_rad) << "," << formatRoundTrip(r.z_m) << ","
        << toString(r.map_status) << "," << r.map_reachable << "," << r.audit_reachable << ","
        << formatRoundTrip(r.H_map) << "," << formatRoundTrip(r.H_audit) << ","
        << formatRoundTrip(r.gap) << "," << formatRoundTrip(r.manipulability_map) << ","
        << formatRoundTrip(r.manipulability_audit) << "," << r.solutions << "," << r.on_pose
        << "\n";
  const std::string csv_name = m.name + "_audit.csv";
  out.text(sub + "/" + csv_name, csv.str());
  std::ostringstream md;
  md << "Audit against an independent search: " << a.cells << " cells drawn at random (seed "
     << a.seed << "), " << a.starts
     << " random starts each, every start solved onto the pose and optimised with this map's "
     << "objective, without the map's chaining or neighbours. Of the " << a.both_reachable
     << " cells both reach, " << formatFixedOr(100.0 * a.shareWithin1Percent(), 1, "-")
     << " % are within 1 % of the audit's best "
     << "objective ("
     << formatFixedOr(a.both_reachable ? 100.0 * a.within_5pct / a.both_reachable : 100.0, 1, "-")
     << " % within 5 %; worst gap " << formatFixedOr(100.0 * a.worst_gap, 2, "-")
     << " %). Reachability verdicts contradicted "
     << "(map: unreachable, audit: a collision-free solution): " << a.reach_contradicted << ".";
  for (int k = 1; k < kReachStatusCount; ++k)
    if (a.verdicts[k] > 0)
      md << " `" << toString(static_cast<ReachStatus>(k)) << "`: " << a.contradicted[k] << " of "
         << a.verdicts[k] << " contradicted.";
  md << " Cells: `" << csv_name << "`.";
  return report::Document().paragraph(md.str());
}

}  // namespace armstudy::dexterity
