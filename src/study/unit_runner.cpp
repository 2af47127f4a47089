#include "study/unit_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "common/errors.hpp"
#include "common/format.hpp"
#include "io/files.hpp"
#include "study/checkpoint.hpp"

namespace armstudy {

UnitTimeRecord UnitTimeRecord::fromEnvironment() {
  const char* p = std::getenv("ARMSTUDY_UNIT_TIMES");
  return UnitTimeRecord{p ? std::string(p) : std::string()};
}

void UnitTimeRecord::append(const std::vector<Line>& lines) const {
  if (!enabled() || lines.empty()) return;
  const bool fresh = !std::filesystem::exists(path) || std::filesystem::file_size(path) == 0;
  std::ofstream f(path, std::ios::app);
  if (!f) throw std::runtime_error("cannot write the unit-time record " + path);
  if (fresh) f << "unit,seconds,cpu_seconds,threads,rank,bytes,part\n";
  for (const Line& l : lines) {
    f << l.unit << ',' << formatFixed(l.seconds, 6) << ',' << formatFixed(l.cpu_seconds, 6) << ','
      << l.threads << ',' << l.rank << ',' << l.bytes << ',';
    if (l.part >= 0) f << l.part;
    f << '\n';
  }
}

double UnitTimeRecord::processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

long UnitRunner::run(const UnitBatch& batch) const {
  std::vector<std::size_t> todo;
  long resumed = 0;
  for (std::size_t k = 0; k < batch.ids.size(); ++k) {
    std::string bytes;
    if (store_.load(batch.ids[k], bytes) && batch.load(k, bytes))
      ++resumed;
    else
      todo.push_back(k);
  }
  if (todo.empty()) return resumed;
  const auto save = [&](std::size_t k, const std::string& bytes) {
    store_.save(batch.ids[k], bytes);
  };
  if (!times_.enabled() && !cancelled_) {
    batch.compute(todo, save);
    return resumed;
  }
  // Slices of units, one call each: one unit when timed, else (cancellable) as many as there are
  // threads, with cancelled_ asked before each. Every call replaces the previous one's units, so
  // the units of the earlier calls are handed back to the stage through `load` (UnitBatch).
  const std::size_t slice = times_.enabled() ? 1 : static_cast<std::size_t>(std::max(1, threads_));
  std::vector<std::string> kept(batch.ids.size());
  std::vector<UnitTimeRecord::Line> lines;
  std::size_t last_begin = 0;
  for (std::size_t begin = 0; begin < todo.size(); begin += slice) {
    if (cancelled_ && cancelled_()) throw RunCancelled();
    const std::vector<std::size_t> part(todo.begin() + begin,
                                        todo.begin() + std::min(todo.size(), begin + slice));
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = UnitTimeRecord::processCpuSeconds();
    batch.compute(part, [&](std::size_t j, const std::string& bytes) {
      save(j, bytes);
      kept[j] = bytes;
    });
    if (times_.enabled())
      lines.push_back({batch.ids[part[0]],
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                       UnitTimeRecord::processCpuSeconds() - c0, threads_, 0,
                       kept[part[0]].size()});
    last_begin = begin;
  }
  for (std::size_t i = 0; i < last_begin; ++i)
    ARMSTUDY_CHECK(batch.load(todo[i], kept[todo[i]]),
                   "a unit computed by this run loads back: " + batch.ids[todo[i]]);
  times_.append(lines);
  return resumed;
}

long runUnitBatches(const UnitRunner& runner, const std::vector<UnitBatch>& batches) {
  if (batches.size() == 1 ||
      !std::all_of(batches.begin(), batches.end(), [](const UnitBatch& b) { return b.portable; })) {
    long loaded = 0;
    for (const UnitBatch& b : batches) loaded += runner.run(b);
    return loaded;
  }
  // Unit k of the combined batch is unit k - offset[b] of batch b.
  std::vector<std::size_t> offset;
  UnitBatch all;
  for (const UnitBatch& b : batches) {
    offset.push_back(all.ids.size());
    all.ids.insert(all.ids.end(), b.ids.begin(), b.ids.end());
  }
  const auto owner = [&](std::size_t k) {
    return static_cast<std::size_t>(std::upper_bound(offset.begin(), offset.end(), k) -
                                    offset.begin()) -
           1;
  };
  all.load = [&](std::size_t k, const std::string& bytes) {
    const std::size_t b = owner(k);
    return batches[b].load(k - offset[b], bytes);
  };
  all.compute = [&](const std::vector<std::size_t>& todo, const UnitBatch::Done& done) {
    std::vector<std::vector<std::size_t>> mine(batches.size());
    for (std::size_t k : todo) {
      const std::size_t b = owner(k);
      mine[b].push_back(k - offset[b]);
    }
    for (std::size_t b = 0; b < batches.size(); ++b)
      batches[b].compute(
          mine[b], [&, b](std::size_t j, const std::string& bytes) { done(j + offset[b], bytes); });
  };
  return runner.run(all);
}

std::vector<long> SharedLoop::itemsOf(const std::vector<Chunk>& mine) {
  std::vector<long> out;
  for (const Chunk& c : mine)
    for (long i = c.second.begin; i < c.second.end; ++i) out.push_back(i);
  return out;
}

std::vector<ItemRange> SharedLoop::chunks() const {
  if (ends.empty()) return splitRange(items, chunk);
  ARMSTUDY_CHECK(ends.back() == items, "a shared loop's chunk ends cover its items");
  std::vector<ItemRange> out;
  long begin = 0;
  for (const long e : ends) {
    ARMSTUDY_CHECK(e > begin, "a shared loop's chunk ends ascend");
    out.push_back({begin, e});
    begin = e;
  }
  return out;
}

void SharedLoop::computeAll(const std::vector<Chunk>& mine) const {
  if (!mine.empty()) compute(mine);
  if (finish) finish(mine);
}

void UnitRunner::share(const SharedLoop& loop) const {
  if (loop.items <= 0) return;
  if (!times_.enabled() && !cancelled_) return loop.computeAll({{0, ItemRange{0, loop.items}}});
  if (!times_.enabled()) {
    // Cancellable: the chunks in slices of as many as there are threads, cancelled_ asked before
    // each (nothing of a shared loop is saved; the units before it are).
    const std::vector<ItemRange> ranges = loop.chunks();
    const std::size_t slice = static_cast<std::size_t>(std::max(1, threads_));
    std::vector<SharedLoop::Chunk> all;
    for (std::size_t begin = 0; begin < ranges.size(); begin += slice) {
      if (cancelled_()) throw RunCancelled();
      std::vector<SharedLoop::Chunk> part;
      for (std::size_t k = begin; k < std::min(ranges.size(), begin + slice); ++k)
        part.push_back({k, ranges[k]});
      loop.compute(part);
      all.insert(all.end(), part.begin(), part.end());
    }
    if (loop.finish) loop.finish(all);
    return;
  }
  // Recorded: the loop's chunks, each timed (tests/benchmarks/simulate_distribution.py
  // regroups them as a distributed run of any size would).
  const std::vector<ItemRange> ranges = loop.chunks();
  std::vector<SharedLoop::Chunk> all;
  std::vector<UnitTimeRecord::Line> lines;
  for (std::size_t k = 0; k < ranges.size(); ++k) {
    all.push_back({k, ranges[k]});
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = UnitTimeRecord::processCpuSeconds();
    loop.compute({all.back()});
    lines.push_back({"share:" + loop.id,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                     UnitTimeRecord::processCpuSeconds() - c0, threads_, 0, 0,
                     loop.part ? static_cast<long>(loop.part(k)) : -1L});
  }
  if (loop.finish) loop.finish(all);
  if (loop.pack)
    for (std::size_t k = 0; k < ranges.size(); ++k) lines[k].bytes = loop.pack(k, ranges[k]).size();
  times_.append(lines);
}

std::unique_ptr<RankGroups> UnitRunner::groups(const std::vector<double>&) const { return nullptr; }

RankGroupPlan planRankGroups(const std::vector<double>& weights, int ranks, int min_ranks) {
  RankGroupPlan plan;
  const std::size_t programs = weights.size();
  plan.group_of.assign(programs, 0);
  const std::size_t g =
      std::min<std::size_t>(programs, static_cast<std::size_t>(ranks / std::max(1, min_ranks)));
  if (g < 2) return plan;
  std::vector<std::size_t> order(programs);
  for (std::size_t p = 0; p < programs; ++p) order[p] = p;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return weights[a] > weights[b]; });
  std::vector<double> load(g, 0.0);
  for (const std::size_t p : order) {
    const std::size_t j =
        static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    plan.group_of[p] = j;
    load[j] += weights[p];
  }
  double total = 0;
  for (const double w : load) total += w;
  std::vector<double> share(g);
  plan.ranks.assign(g, 1);
  int given = 0;
  for (std::size_t j = 0; j < g; ++j) {
    share[j] = total > 0 ? ranks * load[j] / total : double(ranks) / double(g);
    plan.ranks[j] = std::max(1, static_cast<int>(share[j]));
    given += plan.ranks[j];
  }
  // Too many (groups raised to one rank): take from the most over their share; too few: give to
  // the most under it (lowest index on ties).
  auto pick = [&](int sign) {
    std::size_t best = g;
    for (std::size_t j = 0; j < g; ++j) {
      if (sign > 0 && plan.ranks[j] <= 1) continue;
      const double d = sign * (plan.ranks[j] - share[j]);
      if (best == g || d > sign * (plan.ranks[best] - share[best])) best = j;
    }
    return best;
  };
  for (; given > ranks; --given) --plan.ranks[pick(+1)];
  for (; given < ranks; ++given) ++plan.ranks[pick(-1)];
  return plan;
}

void runSharedLoop(const UnitRunner* runner, const SharedLoop& loop) {
  if (runner)
    runner->share(loop);
  else if (loop.items > 0)
    loop.computeAll({{0, ItemRange{0, loop.items}}});
}

UnitBatch rangeUnitBatch(std::vector<std::string> ids, std::vector<ItemRange> ranges,
                         std::function<bool(std::size_t k, const std::string& bytes)> load,
                         RangeCompute compute) {
  ARMSTUDY_CHECK(ids.size() == ranges.size(), "rangeUnitBatch: one id per range");
  UnitBatch batch;
  batch.ids = std::move(ids);
  batch.load = std::move(load);
  batch.compute = [ranges = std::move(ranges), compute = std::move(compute)](
                      const std::vector<std::size_t>& units, const UnitBatch::Done& done) {
    std::vector<ItemRange> todo;
    for (std::size_t k : units) todo.push_back(ranges[k]);
    compute(units, todo, [&](std::size_t j, const std::string& bytes) { done(units[j], bytes); });
  };
  return batch;
}

std::vector<std::string> unitIds(const std::string& prefix, const std::vector<ItemRange>& ranges) {
  std::vector<std::string> ids;
  for (const ItemRange& r : ranges) ids.push_back(prefix + r.text());
  return ids;
}

}  // namespace armstudy
