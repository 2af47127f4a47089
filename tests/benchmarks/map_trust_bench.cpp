// Map trust benchmark (docs/performance.md, "## Map trust"): how far the shipped maps are
// from searches that do not share the solver's path, and what the map search costs.
//  - Dexterity (studies/stem_heatmap.toml, thesis Fig. 3.6): the map with and without the map
//    search (seeded multi-starts + neighbour propagation), each against the audit (500 random
//    cells, 200 random starts each), the chained rows ascending vs descending in gamma, and a
//    sub-range study (gamma from 0 deg) against the full map on the shared cells.
//  - Reach (studies/spraying_row.toml, thesis Fig. 3.8 grid, self-collision checked): the sweep
//    with and without the map search against the audit (500 poses, 500 random starts each), and
//    the statuses with the grid lines swept in the other direction.
// Run: cmake --build build --target map_trust_bench && build/tests/benchmarks/map_trust_bench
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "dexterity/dexterity_audit.hpp"
#include "engine/study_file.hpp"
#include "reach/reach_audit.hpp"
#include "stages/reach/reach_config.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;

namespace {

// Share of the cells reachable in both maps whose optimised objective agrees within `tol`
// (relative to the better of the two), and the count of cells differing in reachability.
struct Agreement {
  int both = 0, within = 0, reach_differs = 0;
  double share() const { return both ? double(within) / both : 1.0; }
};
Agreement agree(const DexterityMap& a, const DexterityMap& b, int b_gamma_offset, double tol) {
  Agreement r;
  const int Ga = a.grid.gamma_rad.count, Gb = b.grid.gamma_rad.count;
  for (int iz = 0; iz < b.grid.z_m.count; ++iz)
    for (int jg = 0; jg < Gb; ++jg) {
      const CellResult& cb = b.cells[b.grid.index(jg, iz)];
      const CellResult& ca = a.cells[iz * Ga + jg + b_gamma_offset];
      if (ca.reachable != cb.reachable) ++r.reach_differs;
      if (!(ca.reachable && cb.reachable)) continue;
      ++r.both;
      const double best = std::min(ca.H_opt, cb.H_opt);
      r.within += std::abs(ca.H_opt - cb.H_opt) <= tol * std::max(std::abs(best), 1e-12) ? 1 : 0;
    }
  return r;
}

void auditRow(const char* what, const Model& m, const DexterityOptions& o, const DexterityMap& map,
              int threads) {
  const DexterityAudit a = auditDexterityMap(m, o, map, threads);
  std::printf("| %s | %.3f | %d | %.2f %% | %.2f %% | %.1f %% | %d | %.1f |\n", what, map.seconds,
              a.both_reachable, 100.0 * a.shareWithin1Percent(),
              a.both_reachable ? 100.0 * a.within_5pct / a.both_reachable : 100.0,
              100.0 * a.worst_gap, a.reach_contradicted, a.seconds);
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void reachPart(int threads, int collision_starts, int audit_poses) {
  Study study = loadStudy(armstudy::test::sourcePath("studies/spraying_row.toml"));
  const Model& m = study.designs.at(0).model;
  ReachConfig cfg = *stageSettings<ReachConfig>(study, "reach");
  if (collision_starts >= 0) cfg.search.collision_starts = collision_starts;
  const TaskGrid& g = cfg.grids.at(0);
  std::printf(
      "\nReach: %s, grid %s (%ld poses, studies/spraying_row.toml), %d threads; audit %d poses x "
      "500 starts\n\n",
      m.name.c_str(), g.name.c_str(), g.size(), threads, audit_poses);
  std::printf(
      "| sweep | wall [s] | self_collision | audited self_collision | contradicted | reachable, "
      "audit found none | "
      "manipulability within 5 %% of the audit's best | audit [s] "
      "|\n|---|---|---|---|---|---|---|---|\n");
  const int sc = static_cast<int>(ReachStatus::SelfCollision);
  auto row = [&](const char* what, const PoseSweep& s, double wall) {
    const ReachAudit a = auditGridSweep(m, g, cfg.ik, cfg.collision, s, audit_poses, 500,
                                        defaults::kAuditSeed, threads);
    long n = 0;
    for (long i = 0; i < s.size; ++i) n += s.status[i] == sc;
    std::printf("| %s | %.3f | %ld | %d | %d | %d | %d of %d | %.1f |\n", what, wall, n,
                a.by_status[sc], a.contradicted[sc], a.audit_missed, a.manipulability_within_5pct,
                a.manipulability_compared, a.seconds);
  };
  auto t0 = std::chrono::steady_clock::now();
  IkOptions one_way = cfg.ik;  // one chain per line, without the map search
  one_way.sweep_both_directions = false;
  PoseSweep raw = sweepGrid(m, g, one_way, threads, nullptr, cfg.collision);
  const double t_raw = seconds(t0);
  row("one-way sweep alone (map search off)", raw, t_raw);
  t0 = std::chrono::steady_clock::now();
  PoseSweep up = sweepGrid(m, g, cfg.ik, threads, nullptr, cfg.collision);
  const SweepSearchSummary ss =
      searchGridSweep(m, g, cfg.ik, threads, cfg.collision, cfg.search, up);
  row("both-way sweep + map search (shipped)", up, seconds(t0));
  IkOptions rev = cfg.ik, rev_one_way = one_way;
  rev.sweep_descending = rev_one_way.sweep_descending = true;
  PoseSweep raw_down = sweepGrid(m, g, rev_one_way, threads, nullptr, cfg.collision);
  PoseSweep down = sweepGrid(m, g, rev, threads, nullptr, cfg.collision);
  searchGridSweep(m, g, rev, threads, cfg.collision, cfg.search, down);
  long d_raw = 0, d = 0, both_raw = 0, m_raw = 0, both = 0, m5 = 0;
  auto close = [](double a, double b) { return std::abs(a - b) <= 0.05 * std::max(a, b); };
  for (long i = 0; i < up.size; ++i) {
    d_raw += raw.status[i] != raw_down.status[i];
    d += up.status[i] != down.status[i];
    if (raw.reachable(i) && raw_down.reachable(i))
      ++both_raw, m_raw += !close(raw.manipulability[i], raw_down.manipulability[i]);
    if (up.reachable(i) && down.reachable(i))
      ++both, m5 += !close(up.manipulability[i], down.manipulability[i]);
  }
  std::printf(
      "\nManipulability at the solution differing by more than 5 %% with the other direction: "
      "one-way sweep alone "
      "%.1f %% of %ld poses, shipped %.1f %% of %ld.",
      100.0 * m_raw / std::max(1L, both_raw), both_raw, 100.0 * m5 / std::max(1L, both), both);
  std::printf(
      "\nStatuses differing with the lines swept in the other direction: one-way sweep alone %ld, "
      "shipped "
      "%ld (of %ld poses).\nMap search: %d propagation rounds (%ld neighbour tries, %ld updates), "
      "%ld poses "
      "in collision x %d seeded starts (%ld tries, %ld freed), wider neighbourhood (%ld tries, %ld "
      "freed), %d best-manipulability rounds (%ld tries, %ld updates), %.3f s\n",
      d_raw, d, up.size, ss.rounds, ss.neighbour_tries, ss.neighbour_updates, ss.multistart_poses,
      cfg.search.collision_starts, ss.multistart_tries, ss.multistart_freed, ss.box_tries,
      ss.box_freed, ss.best_rounds, ss.best_tries, ss.best_updates, ss.seconds);
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = 2;
  if (argc > 1 && std::string(argv[1]) == "reach") {
    // optional: seeded starts per pose in collision (-1: the study's), poses audited
    reachPart(threads, argc > 2 ? std::atoi(argv[2]) : -1, argc > 3 ? std::atoi(argv[3]) : 500);
    return 0;
  }
  const Study study = loadStudy(armstudy::test::sourcePath("studies/stem_heatmap.toml"));
  const Model& m = study.designs.at(0).model;
  DexterityOptions o = *stageSettings<DexterityOptions>(study, "dexterity");
  o.audit_cells = 500;
  o.audit_starts = defaults::kAuditDexterityStarts;
  std::printf(
      "Map trust: %s, %d cells (studies/stem_heatmap.toml), %d threads; audit %d cells x %d "
      "starts\n\n",
      m.name.c_str(), o.grid.size(), threads, o.audit_cells, o.audit_starts);
  std::printf(
      "| map | wall [s] | audited cells reached by both | within 1 %% | within 5 %% | worst gap | "
      "reachability contradicted | audit [s] |\n|---|---|---|---|---|---|---|---|\n");
  DexterityOptions chain = o;
  chain.seed_starts = 0;
  chain.propagation_rounds = 0;
  const DexterityMap m_chain = computeDexterityMap(m, chain, threads);
  auditRow("chained rows only (map search off)", m, chain, m_chain, threads);
  const DexterityMap m_full = computeDexterityMap(m, o, threads);
  auditRow("chained rows + map search (shipped)", m, o, m_full, threads);

  std::printf(
      "\n| comparison | cells reached by both | within 1 %% | reachability differs "
      "|\n|---|---|---|---|\n");
  DexterityOptions desc = o, chain_desc = chain;
  desc.descending = chain_desc.descending = true;
  const DexterityMap m_chain_desc = computeDexterityMap(m, chain_desc, threads);
  Agreement a = agree(m_chain, m_chain_desc, 0, defaults::kAuditTolerance);
  std::printf("| chained only: gamma ascending vs descending | %d | %.2f %% | %d |\n", a.both,
              100 * a.share(), a.reach_differs);
  const DexterityMap m_desc = computeDexterityMap(m, desc, threads);
  a = agree(m_full, m_desc, 0, defaults::kAuditTolerance);
  std::printf("| with map search: gamma ascending vs descending | %d | %.2f %% | %d |\n", a.both,
              100 * a.share(), a.reach_differs);
  // Sub-range: gamma from 0 deg (the full grid's middle value) to the same maximum.
  DexterityOptions sub = o, chain_sub = chain;
  const int G = o.grid.gamma_rad.count, off = (G - 1) / 2;
  for (DexterityOptions* s : {&sub, &chain_sub}) {
    s->grid.gamma_rad.min = o.grid.gamma_rad.value(off);
    s->grid.gamma_rad.count = G - off;
  }
  a = agree(m_chain, computeDexterityMap(m, chain_sub, threads), off, defaults::kAuditTolerance);
  std::printf("| chained only: gamma from %.0f deg vs full map | %d | %.2f %% | %d |\n",
              sub.grid.gamma_rad.min * 180 / M_PI, a.both, 100 * a.share(), a.reach_differs);
  a = agree(m_full, computeDexterityMap(m, sub, threads), off, defaults::kAuditTolerance);
  std::printf("| with map search: gamma from %.0f deg vs full map | %d | %.2f %% | %d |\n",
              sub.grid.gamma_rad.min * 180 / M_PI, a.both, 100 * a.share(), a.reach_differs);
  std::printf(
      "\nMap search of the shipped map: %d seeding cells, %ld multi-start tries (%d cells "
      "improved), %d "
      "propagation rounds, %ld neighbour tries (%d updates), %.3f s\n",
      m_full.search.seeding_cells, m_full.search.multistart_tries,
      m_full.search.multistart_improved, m_full.search.rounds, m_full.search.neighbour_tries,
      m_full.search.neighbour_improved, m_full.search.seconds);
  // Where the valley of the shipped map lies (docs/dexterity.md, "What our model finds").
  double best = 0;
  for (const CellResult& c : m_full.cells)
    if (c.reachable) best = std::max(best, c.opt.manipulability);
  std::printf(
      "\n| z [m] | row mean | row min | at gamma [deg] | at gamma 90 deg "
      "|\n|---|---|---|---|---|\n");
  for (int iz = 30; iz < o.grid.z_m.count; iz += 10) {
    double mn = 1e9, at = 0, sum = 0;
    int n = 0;
    for (int ig = 0; ig < G; ++ig) {
      const CellResult& c = m_full.cells[o.grid.index(ig, iz)];
      if (!c.reachable) continue;
      const double v = c.opt.manipulability / best;
      sum += v;
      ++n;
      if (v < mn) mn = v, at = o.grid.gamma_rad.value(ig) * 180 / M_PI;
    }
    std::printf("| %.2f | %.3f | %.3f | %.0f | %.3f |\n", o.grid.z_m.value(iz), n ? sum / n : 0.0,
                mn, at, m_full.cells[o.grid.index(G - 1, iz)].opt.manipulability / best);
  }
  reachPart(threads, -1, 500);
  return 0;
}
