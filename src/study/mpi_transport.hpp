#pragma once
// Private to study/distributed.cpp: how the ranks wait and exchange bytes (MPI builds only).
#ifdef ARMSTUDY_MPI
// The C API only (OpenMPI and MPICH would otherwise pull in their deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace armstudy::mpi {

// Waits for a request, sleeping between tests (an idle rank leaves its core to the others).
void waitQuietly(MPI_Request& req);
// Waits for a message with `tag` from `source` (MPI_ANY_SOURCE allowed), sleeping between probes.
MPI_Status probeQuietly(int source, int tag);
// Broadcasts `bytes` (sized on `root` only) from `root`, in pieces whose counts fit an int.
void broadcast(std::string& bytes, int root, std::uint64_t size, MPI_Comm comm = MPI_COMM_WORLD);
// Every rank's `mine`, on every rank of `comm` (rank and size: this rank's in comm) (sizes first:
// ranks still computing are waited for without spinning; then one allgather, or a broadcast per
// rank when the total exceeds an int count).
std::vector<std::string> allGather(const std::string& mine, int rank, int size,
                                   MPI_Comm comm = MPI_COMM_WORLD);

// Packed units: (int64 index, double seconds, double CPU seconds, uint64 length, bytes)...
struct PackedUnit {
  std::size_t k;
  double seconds, cpu_seconds;
  std::string bytes;
};
void pack(std::string& out, const PackedUnit& u);
std::vector<PackedUnit> unpack(const std::string& in);

}  // namespace armstudy::mpi

#endif  // ARMSTUDY_MPI
