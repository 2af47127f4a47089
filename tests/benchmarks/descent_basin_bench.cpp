// Null-space descents and where they end (docs/performance.md, "Null-space descents per stem
// map"): one stem map computed with the steepest descent and with the quasi-Newton directions
// ([dexterity.solver] quasi_newton), compared cell by cell (also with the descents stopped by the
// projected gradient alone, and with the collision term w_c = 1 in the objective); then the cells
// where the quasi-Newton map is worst, looked at with searches that do not share the map's path:
//  - a many-start search (the audit's own, dexterity_audit.hpp) with steepest descents;
//  - the projected gradient at both maps' optima, and a long steepest descent (no
//    relative-improvement or gradient stop) from each: whether it is a local optimum (it stays) or
//    not (it moves on and improves), and whether that descent ends in contact;
//  - the clearance of both maps' postures;
//  - the descents from the eight neighbours' steepest optima (what the neighbour propagation
//    tries), by each method: how many end at each map's value.
// Run: cmake --build build --target descent_basin_bench && build/tests/benchmarks/
//      descent_basin_bench [study] [design index] [threads] [cells to inspect] [audit starts]
// (defaults: studies/stem_heatmap.toml 0 2 6 1000).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "common/angles.hpp"
#include "dexterity/dexterity_audit.hpp"
#include "dexterity/stem_collision.hpp"
#include "engine/study_file.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;

namespace {

constexpr double kWorse = 0.01;          // a cell this much worse (relative H) counts as worse
constexpr double kSlightlyWorse = 1e-3;  // and this much, as slightly worse
constexpr double kBetter = 1e-5;         // a cell this much better counts as better
constexpr double kSameValue = 1e-5;      // relative H of one optimum reached twice
constexpr int kLongDescent = 20000;      // iterations of the reference steepest descent
constexpr int kAuditAll = 200;           // maps of at most this many cells: every cell audited

struct Variant {
  const char* name;
  bool quasi_newton;
  double relative_improvement;  // < 0: the study's
  double w_collision = 0;       // w_c of eq. (5.51)
};

struct Computed {
  Variant v;
  DexterityMap map;
  ik::DescentTally all;
};

Computed compute(const Model& m, DexterityOptions o, const Variant& v, int threads) {
  o.nullspace.quasi_newton = v.quasi_newton;
  if (v.relative_improvement >= 0) o.nullspace.relative_improvement = v.relative_improvement;
  o.w_collision = v.w_collision;
  Computed c{v, computeDexterityMap(m, o, threads), {}};
  for (const ik::DescentTally* t :
       {&c.map.search.chain, &c.map.search.seed, &c.map.search.neighbour, &c.map.search.collision})
    c.all.add(*t);
  return c;
}

double relative(double H, double H_ref) { return (H - H_ref) / std::max(std::abs(H_ref), 1e-12); }

// Cells of `b` worse than `a` by more than kWorse, worst first.
std::vector<int> worstCells(const DexterityMap& a, const DexterityMap& b) {
  std::vector<int> idx;
  for (int k = 0; k < static_cast<int>(a.cells.size()); ++k)
    if (a.cells[k].reachable && b.cells[k].reachable &&
        relative(b.cells[k].H_opt, a.cells[k].H_opt) > kWorse)
      idx.push_back(k);
  std::sort(idx.begin(), idx.end(), [&](int i, int j) {
    return relative(b.cells[i].H_opt, a.cells[i].H_opt) >
           relative(b.cells[j].H_opt, a.cells[j].H_opt);
  });
  return idx;
}

void compareRow(const Computed& ref, const Computed& c) {
  int worse = 0, slightly = 0, better = 0;
  double worst = 0;
  for (std::size_t k = 0; k < ref.map.cells.size(); ++k) {
    const CellResult &a = ref.map.cells[k], &b = c.map.cells[k];
    if (!(a.reachable && b.reachable)) continue;
    const double r = relative(b.H_opt, a.H_opt);
    worse += r > kWorse;
    slightly += r > kSlightlyWorse;
    better += r < -kBetter;
    worst = std::max(worst, r);
  }
  std::printf("| %s | %.2f | %ld | %.2f M | %.1f | %.1f | %d | %d | %d | %.2f %% |\n", c.v.name,
              c.map.seconds, c.all.descents, 1e-6 * c.all.kernel_evaluations,
              double(c.all.iterations) / std::max(1L, c.all.descents),
              double(c.all.kernel_evaluations) / std::max(1L, c.all.descents), worse, slightly,
              better, 100 * worst);
}

struct Descender {
  const Model& m;
  const DexterityOptions& o;
  KinematicsWorkspace ws;
  IkWorkspace ik_ws;
  ik::ObjectiveContext ctx;
  ik::WeightedObjective obj;
  JointVector w_inv;
  Descender(const Model& m, const DexterityOptions& o)
      : m(m), o(o), ws(m), ik_ws(m), ctx(m, ws), obj(o.buildObjective(m)) {
    w_inv = JointVector::Ones(m.dof());
  }
  // The descent from `q` (on the pose) with `ns`.
  ik::NullspaceResult descend(const StemGrid::Cell& cell, const JointVector& q,
                              const ik::NullspaceOptions& ns) {
    ctx.u_W = cell.u_W;
    return ik::optimiseAtPose(m, ws, ctx, cell.target, q, obj, w_inv, ns);
  }
  double gradient(const StemGrid::Cell& cell, const JointVector& q) {
    ctx.u_W = cell.u_W;
    return ik::projectedGradient(m, ws, ctx, cell.target, q, obj, w_inv);
  }
};

// The joint closest to a limit at q (as "j<index> <distance>").
std::string nearestLimit(const Model& m, const JointVector& q) {
  int best = 0;
  double dist = 1e9;
  for (int i = 0; i < q.size(); ++i) {
    const double d = std::min(q[i] - m.joints[i].limits.q_min, m.joints[i].limits.q_max - q[i]);
    if (d < dist) dist = d, best = i;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s %.1e", m.joints[best].name.c_str(), dist);
  return buf;
}

int neighbourCells(const StemGrid& g, int idx, int out[8]) {
  const int G = g.gamma_rad.count, Z = g.z_m.count, ig = idx % G, iz = idx / G;
  int n = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dg = -1; dg <= 1; ++dg) {
      const int jg = ig + dg, jz = iz + dz;
      if ((dz || dg) && jg >= 0 && jg < G && jz >= 0 && jz < Z) out[n++] = g.index(jg, jz);
    }
  return n;
}

// Whether the steepest descent from `q` (no stop but the iteration cap) ends in contact: the
// settled cell keeps its start instead (settleCollision).
struct LongDescent {
  ik::NullspaceResult r;
  bool contact = false;
};
LongDescent longDescent(Descender& d, collision::CollisionWorkspace& cws,
                        const StemGrid::Cell& cell, const JointVector& q,
                        const ik::NullspaceOptions& ns) {
  LongDescent out{d.descend(cell, q, ns), false};
  CellResult r;
  r.reachable = true;
  r.q_plain = q;
  r.q_opt = out.r.q;
  settleCollision(d.m, d.ws, &cws, d.o.collisionFor(d.m), r);
  out.contact = r.q_opt != out.r.q;
  return out;
}

// The worst cells of `c` against the steepest map `ref`, each against the searches above.
void inspect(const Model& m, const DexterityOptions& o, const Computed& ref, const Computed& c,
             int count, int starts, int threads) {
  const std::vector<int> worst = worstCells(ref.map, c.map);
  std::vector<int> cells(worst.begin(), worst.begin() + std::min<int>(count, worst.size()));
  if (cells.empty()) return;
  DexterityOptions so = o;
  so.nullspace.quasi_newton = false;
  const DexterityAudit a = auditDexterityCells(m, so, ref.map, cells, starts, 11, threads);
  std::printf(
      "\n%s: %zu cells > 1 %% worse than steepest; the worst %zu against a %d-start steepest "
      "search\n\n| gamma [deg] | z [m] | H steepest | H quasi-Newton | worse | max_i |dq_i| "
      "between them | H many-start | clearance steepest / quasi-Newton [mm] | projected "
      "gradient steepest / quasi-Newton | long descent from steepest's: dH, moved, ends in "
      "contact | from quasi-Newton's | from the neighbours' steepest optima: steepest ends at "
      "steepest's / quasi-Newton's value | quasi-Newton ends at steepest's / its value |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      c.v.name, worst.size(), cells.size(), starts);
  Descender d(m, o);
  collision::CollisionWorkspace cws(m);
  ik::NullspaceOptions longsd = so.nullspace;
  longsd.relative_improvement = 0;
  longsd.gradient_tolerance = 0;
  longsd.max_iterations = kLongDescent;
  DexterityOptions oq = o;
  oq.nullspace.quasi_newton = c.v.quasi_newton;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const int idx = cells[k];
    const StemGrid::Cell cell =
        o.grid.cell(idx % o.grid.gamma_rad.count, idx / o.grid.gamma_rad.count);
    const CellResult &A = ref.map.cells[idx], &B = c.map.cells[idx];
    const LongDescent la = longDescent(d, cws, cell, A.q_opt, longsd);
    const LongDescent lb = longDescent(d, cws, cell, B.q_opt, longsd);
    int nb[8];
    const int nn = neighbourCells(o.grid, idx, nb);
    int sd_a = 0, sd_b = 0, qn_a = 0, qn_b = 0, tried = 0;
    const auto same = [](double H, double H_ref) {
      return std::abs(relative(H, H_ref)) < kSameValue;
    };
    for (int j = 0; j < nn; ++j) {
      CellResult rs, rq;
      collision::CollisionWorkspace* cw = o.collisionFor(m).enabled() ? &cws : nullptr;
      const JointVector& seed = ref.map.cells[nb[j]].q_opt;
      if (!cellFromSeed(m, d.ws, d.ik_ws, d.ctx, d.obj, so, cell, seed, rs, cw, false) ||
          !cellFromSeed(m, d.ws, d.ik_ws, d.ctx, d.obj, oq, cell, seed, rq, cw, false))
        continue;
      ++tried;
      sd_a += same(rs.H_opt, A.H_opt);
      sd_b += same(rs.H_opt, B.H_opt);
      qn_a += same(rq.H_opt, A.H_opt);
      qn_b += same(rq.H_opt, B.H_opt);
    }
    std::printf(
        "| %.0f | %.2f | %.6f | %.6f | %.2f %% | %.3f | %.6f | %.1f / %.1f | %.1e / %.1e | %.1e, "
        "%.3f, %s | %.1e, %.3f, %s | %d / %d of %d | %d / %d |\n",
        toDegrees(cell.gamma), cell.z, A.H_opt, B.H_opt, 100 * relative(B.H_opt, A.H_opt),
        (A.q_opt - B.q_opt).cwiseAbs().maxCoeff(), a.rows[k].H_audit, 1e3 * A.min_distance_m,
        1e3 * B.min_distance_m, d.gradient(cell, A.q_opt), d.gradient(cell, B.q_opt),
        la.r.H_final - A.H_opt, (la.r.q - A.q_opt).cwiseAbs().maxCoeff(), la.contact ? "yes" : "no",
        lb.r.H_final - B.H_opt, (lb.r.q - B.q_opt).cwiseAbs().maxCoeff(), lb.contact ? "yes" : "no",
        sd_a, sd_b, tried, qn_a, qn_b);
  }
}

// Small maps: every cell of each map against the audit's many-start search (steepest descents).
void auditAll(const Model& m, const DexterityOptions& o, const std::vector<const Computed*>& maps,
              int starts, int threads) {
  std::vector<int> cells(o.grid.size());
  std::iota(cells.begin(), cells.end(), 0);
  DexterityOptions so = o;
  so.nullspace.quasi_newton = false;
  std::printf(
      "\nEvery cell against a %d-start steepest search\n\n| descent | cells reached by both | "
      "within 1 %% | worst gap | mean manipulability, optimised |\n|---|---|---|---|---|\n",
      starts);
  for (const Computed* c : maps) {
    const DexterityAudit a = auditDexterityCells(m, so, c->map, cells, starts, 11, threads);
    double sum = 0;
    int n = 0;
    for (const CellResult& r : c->map.cells)
      if (r.reachable) sum += r.opt.manipulability, ++n;
    std::printf("| %s | %d | %d | %.2f %% | %.6f |\n", c->v.name, a.both_reachable, a.within_1pct,
                100 * a.worst_gap, n ? sum / n : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string study_path = argc > 1 ? argv[1] : "studies/stem_heatmap.toml";
  const int design = argc > 2 ? std::atoi(argv[2]) : 0;
  const int threads = argc > 3 ? std::atoi(argv[3]) : 2;
  const int count = argc > 4 ? std::atoi(argv[4]) : 6;
  const int starts = argc > 5 ? std::atoi(argv[5]) : 1000;
  const Study study = loadStudy(armstudy::test::sourcePath(study_path));
  const Model& m = study.designs.at(design).model;
  const DexterityOptions o = *stageSettings<DexterityOptions>(study, "dexterity");
  std::printf("Descents and basins: %s, %d cells (%s), %d threads\n\n", m.name.c_str(),
              o.grid.size(), study_path.c_str(), threads);
  std::printf(
      "| descent | map [s] | descents | kernel evaluations | iterations / descent | kernel "
      "evaluations / descent | cells > 1 %% worse than steepest | > 0.1 %% worse | better by > "
      "1e-5 | worst |\n|---|---|---|---|---|---|---|---|---|---|\n");
  const Computed sd = compute(m, o, {"steepest", false, -1}, threads);
  compareRow(sd, sd);
  const Computed qn = compute(m, o, {"quasi-Newton (shipped)", true, -1}, threads);
  compareRow(sd, qn);
  compareRow(sd, compute(m, o, {"quasi-Newton, stopped by the projected gradient alone", true, 0},
                         threads));
  // With the collision term the objective differs: each against the steepest map of its own.
  const Computed sdc = compute(m, o, {"steepest, w_c = 1", false, -1, 1}, threads);
  compareRow(sdc, sdc);
  compareRow(sdc, compute(m, o, {"quasi-Newton, w_c = 1 (against steepest, w_c = 1)", true, -1, 1},
                          threads));
  inspect(m, o, sd, qn, count, starts, threads);
  if (o.grid.size() <= kAuditAll) auditAll(m, o, {&sd, &qn}, starts, threads);
  return 0;
}
