#pragma once
// Distributed study runs (docs/distributed.md): the processes ("ranks") of one MPI job run the same
// study in lockstep. Every rank runs every stage, so every rank reaches the same UnitBatch in the
// same order; the distributed UnitRunner splits each batch's units among the ranks (rank 0 hands
// them out on demand, in shrinking chunks, and computes too), every rank saves the units it
// computed into the checkpoint store (a shared filesystem) and, at the end of the batch, receives
// the bytes of all units computed elsewhere, so each rank merges the whole batch exactly as a
// single process does. Only rank 0 writes into the output folder; the other ranks write their
// (identical) files into a private scratch folder that is removed. Results are therefore
// byte-identical for any number of ranks and threads.
//
// MPI itself stays inside distributed.cpp (built with the CMake option ARMSTUDY_MPI); without it
// only the single process exists.
#include <memory>
#include <stdexcept>
#include <string>

#include "study/stage.hpp"

namespace armstudy {

class CheckpointStore;

// The processes of one run. A single process is rank 0 of 1.
class Ranks {
 public:
  virtual ~Ranks() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool root() const { return rank() == 0; }
  bool distributed() const { return size() > 1; }
  // Collective (every rank calls it): the lowest rank that passed failed = true, or size() when
  // none did. Waits without spinning (idle ranks leave the cores to the busy ones).
  virtual int firstFailure(bool failed) const = 0;
  // The unit runner of one study run over `store`; `progress`: rank 0 reports the job's units;
  // `group_ranks`: RunOptions::search_group_ranks.
  virtual std::unique_ptr<UnitRunner> unitRunner(const CheckpointStore& store, int threads,
                                                 bool progress, int group_ranks) const = 0;
  // Ends the whole job after an error on this rank (the other ranks would otherwise wait for it).
  [[noreturn]] virtual void abortJob(int exit_code) const = 0;
};

// A single process: rank 0 of 1.
const Ranks& singleProcess();

// Thrown on the ranks that did not fail when another rank failed and reported its error (exit
// quietly: the message was printed once, by that rank).
struct OtherRankFailed : std::runtime_error {
  OtherRankFailed() : std::runtime_error("another rank of the MPI job failed") {}
};

// Whether this armstudy was built with MPI (CMake option ARMSTUDY_MPI).
bool mpiAvailable();

// The MPI job this process was started in by a launcher (mpirun, mpiexec, srun): initializes MPI;
// destroying the returned object finalizes it. Null when no launcher started this process (a plain
// `armstudy run`). Throws InputError when a launcher started several ranks but this armstudy was
// built without MPI.
std::unique_ptr<Ranks> joinMpiJob();

}  // namespace armstudy
