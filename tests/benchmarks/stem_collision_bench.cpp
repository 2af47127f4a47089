// Stem maps with and without collisions (docs/performance.md, "Stem maps with collisions"): the
// thesis row study (studies/stem_row.toml: Fig. 3.6 stem, full circle, the stem and its
// neighbours at 0.192 m, self-collision, w_c H_c) on a finer grid, each map with its search and
// its audit, against the same map with no collision model and no H_c; ratios to the map without
// collisions of the same run.
#include <algorithm>
#include <cstdio>
#include <ctime>

#include "dexterity/dexterity_audit.hpp"
#include "engine/study_file.hpp"
#include "study/stage.hpp"
#include "test_support.hpp"

using namespace armstudy;
using namespace armstudy::dexterity;

namespace {
constexpr int kThreads = 2;
constexpr int kAuditCells = 100;
constexpr int kAuditStarts = 50;
constexpr int kRepeats = 2;  // each run's best of this many (the machine is shared)
// Process CPU time (all threads): less sensitive than wall time to other load on the machine.
double cpu() { return double(std::clock()) / CLOCKS_PER_SEC; }
}  // namespace

int main() {
  const Study study = loadStudy(armstudy::test::sourcePath("studies/stem_row.toml"));
  const Model& m = study.designs.at(0).model;
  DexterityOptions with = *stageSettings<DexterityOptions>(study, "dexterity");
  with.grid.gamma_rad = {-M_PI, M_PI - M_PI / 90, 180};  // 2 deg
  with.grid.z_m = {0.5, 1.3, 17};                        // 5 cm
  with.audit_cells = kAuditCells;
  with.audit_starts = kAuditStarts;
  with.row_sweep.clear();
  DexterityOptions self_only = with;
  self_only.collision.obstacles.clear();
  DexterityOptions without = with;
  without.collision = StemCollision{};
  without.w_collision = 0;
  std::printf(
      "Stem maps with and without collisions: %s, %d cells (studies/stem_row.toml at 2 deg "
      "x 5 cm), %d threads; audit %d cells x %d starts\n\n",
      m.name.c_str(), with.grid.size(), kThreads, kAuditCells, kAuditStarts);
  std::printf(
      "| map | reachable | map + search, CPU [s] | audit, CPU [s] | total, CPU [s] | ratio "
      "|\n");
  std::printf("|---|---|---|---|---|---|\n");
  double base = 0;
  const std::pair<const char*, const DexterityOptions*> runs[] = {
      {"no collisions", &without},
      {"self-collision, w_c H_c", &self_only},
      {"self-collision and the row's stems, w_c H_c", &with}};
  for (const auto& [name, o] : runs) {
    double t_map = 1e300, t_audit = 1e300;
    int reachable = 0;
    for (int k = 0; k < kRepeats; ++k) {
      const double t0 = cpu();
      const DexterityMap map = computeDexterityMap(m, *o, kThreads);
      const double t1 = cpu();
      auditDexterityMap(m, *o, map, kThreads);
      const double t2 = cpu();
      t_map = std::min(t_map, t1 - t0);
      t_audit = std::min(t_audit, t2 - t1);
      reachable = map.reachable();
    }
    if (base == 0) base = t_map + t_audit;
    std::printf("| %s | %d | %.2f | %.2f | %.2f | %.2f |\n", name, reachable, t_map, t_audit,
                t_map + t_audit, (t_map + t_audit) / base);
    std::fflush(stdout);
  }
  return 0;
}
