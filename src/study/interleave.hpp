#pragma once
// Interleaved programs (docs/distributed.md "Interleaved searches"): several independent
// sequences of shared loops, e.g. the reach map searches of every design of a grid, advance
// together, one loop each per collective step, instead of one program after the other.
//
// Each program runs in a thread of its own and gets a runner whose `share(loop)` waits until every
// program still running has reached its next shared loop (or ended); those loops are then run as
// one combined loop through the real runner (their items concatenated in program order), and the
// programs go on. A distributed run therefore pays one barrier per combined step rather than one
// per program step, and a step's cost, concentrated in a few chunks of each program, spreads over
// all ranks. The programs' own work between loops runs concurrently; a loop's compute, finish, pack
// and unpack run on the calling thread while every program waits, so results do not depend on the
// interleaving: a program's loops are the same loops, only grouped (every rank groups alike, since
// which loops a program reaches depends only on the loops' results).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "study/stage.hpp"

namespace armstudy {

// A program: a sequence of shared loops run through the runner it is given (which it must not use
// for UnitRunner::run: only shared loops interleave).
using InterleavedProgram = std::function<void(const UnitRunner* runner)>;

// What lets a distributed run run each program on a group of its processes only
// (UnitRunner::groups): a program's results as bytes, taken on a process that ran it after it
// ended (`pack`) and applied on every other process (`unpack`), which then holds what it would
// hold had it run the program itself; and each program's predicted cost (`weight`), by which the
// groups are formed (their sizes in proportion; results never depend on it).
struct ProgramResults {
  std::function<std::string(std::size_t program)> pack;
  std::function<void(std::size_t program, const std::string& bytes)> unpack;
  std::function<double(std::size_t program)> weight;
};

// Runs `programs` interleaved through `runner` (null: this process alone, as runSharedLoop).
// Returns when all have ended; rethrows the first (by program index) exception a program threw,
// after every program has ended, and a failure of the combined loop itself after telling every
// program to stop. With `results`, the runner may split its processes into groups
// (UnitRunner::groups): each group runs its programs interleaved among its own processes, then
// every program's results go to every process. This spares each process the bookkeeping of the
// other groups' programs and the applying of their every step's rows (docs/distributed.md, "Rank
// groups").
void runInterleaved(const UnitRunner* runner, const std::vector<InterleavedProgram>& programs,
                    const ProgramResults* results = nullptr);

}  // namespace armstudy
