#pragma once
// A loop whose chunks the processes of a distributed run share (UnitRunner::share): what an
// algorithm that distributes its own steps (the reach map search, the audits) sees of the run.
// It names no transport; the runner moves the packed bytes.
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "study/checkpoint.hpp"

namespace armstudy {

class UnitRunner;

// A loop over items [0, items) that a distributed run shares among its processes
// (UnitRunner::share): `compute(mine)` computes the chunks this process owns (ascending k), all in
// one call with the run's threads (so per-call set-up, such as solver workspaces, is paid once per
// loop and process), before `finish(mine)`, which takes the owned chunks' results (e.g. a Jacobi
// step adopts them only then, so no chunk sees another's results). Then `pack(k, r)` returns an
// owned chunk's results as bytes and the other processes apply them with `unpack(k, r, bytes)`;
// empty bytes mean "nothing to apply" (a runner need not send them, and unpack must accept them).
// A single process owns one chunk, all items (pack and unpack are not called) or, when unit costs
// are recorded, its chunks (`chunks()`), each computed and timed in a call of its own.
struct SharedLoop {
  using Chunk = std::pair<std::size_t, ItemRange>;
  static constexpr long kDefaultChunk = 64;
  std::string id;  // names the loop in the unit-cost record ("share:<id>", one line per chunk)
  long items = 0;
  // Items per chunk among processes (owned round-robin) and in a unit-cost record: small for
  // items that each cost much (e.g. an audit's many-start searches), so that they spread.
  long chunk = kDefaultChunk;
  // When not empty: the chunks' ends instead (ascending, the last one `items`), for chunks of
  // different sizes (e.g. interleave.cpp's combined loop keeps each program's own chunks).
  std::vector<long> ends;
  // Optional: the part chunk k belongs to (interleave.cpp: the program whose loop it is), only
  // written to a unit-cost record.
  std::function<std::size_t(std::size_t k)> part;
  // The chunks, in order (chunk k is the k-th range).
  std::vector<ItemRange> chunks() const;
  std::function<void(const std::vector<Chunk>& mine)> compute;
  std::function<void(const std::vector<Chunk>& mine)> finish;  // optional
  std::function<std::string(std::size_t k, const ItemRange& r)> pack;
  std::function<void(std::size_t k, const ItemRange& r, const std::string& bytes)> unpack;
  // The items of `mine`, ascending (the index space a compute call's parallel loop runs over).
  static std::vector<long> itemsOf(const std::vector<Chunk>& mine);
  // Computes `mine` and finishes (the part every runner does alike).
  void computeAll(const std::vector<Chunk>& mine) const;
};

// Runs `loop` through `runner` (shared among the processes of a distributed run) or, when runner is
// null (library calls outside a study run), in this process alone.
void runSharedLoop(const UnitRunner* runner, const SharedLoop& loop);

}  // namespace armstudy
