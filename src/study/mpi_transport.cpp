// The MPI transport of the distributed runner (study/mpi_transport.hpp).
#include "study/mpi_transport.hpp"

#ifdef ARMSTUDY_MPI
#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>
#include <thread>

namespace armstudy::mpi {

namespace {
// Polling of idle waits: from kPollMin doubling to kPollMax, so an idle rank (or rank 0's hand-out
// thread) takes no core from the ranks that compute, yet answers within a fraction of a
// millisecond.
constexpr auto kPollMin = std::chrono::microseconds(20);
constexpr auto kPollMax = std::chrono::microseconds(500);
// Largest piece of one broadcast (MPI counts are int).
constexpr std::size_t kBroadcastPiece = std::size_t(1) << 30;
}  // namespace

// Waits for a request, sleeping between tests.
void waitQuietly(MPI_Request& req) {
  auto pause = kPollMin;
  for (;;) {
    int flag = 0;
    MPI_Test(&req, &flag, MPI_STATUS_IGNORE);
    if (flag) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, kPollMax);
  }
}

// Waits for a message with `tag` from `source` (MPI_ANY_SOURCE allowed), sleeping between probes.
MPI_Status probeQuietly(int source, int tag) {
  auto pause = kPollMin;
  for (;;) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &st);
    if (flag) return st;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, kPollMax);
  }
}

// Broadcasts `bytes` (sized on `root` only) from `root`, in pieces of at most kBroadcastPiece.
void broadcast(std::string& bytes, int root, std::uint64_t size, MPI_Comm comm) {
  bytes.resize(size);
  for (std::size_t at = 0; at < size; at += kBroadcastPiece) {
    const int n = static_cast<int>(std::min<std::size_t>(kBroadcastPiece, size - at));
    MPI_Bcast(bytes.data() + at, n, MPI_BYTE, root, comm);
  }
}

// Every rank's `mine`, on every rank (sizes first: ranks still computing are waited for without
// spinning).
std::vector<std::string> allGather(const std::string& mine, int rank, int size, MPI_Comm comm) {
  const std::uint64_t my_size = mine.size();
  std::vector<std::uint64_t> sizes(size);
  MPI_Request req;
  MPI_Iallgather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, comm, &req);
  waitQuietly(req);
  std::vector<std::string> all(size);
  std::uint64_t total = 0;
  for (std::uint64_t n : sizes) total += n;
  if (total <= static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
    // One collective (log2(size) latencies), as a shared loop's steps need.
    std::vector<int> counts(size), displs(size);
    for (int r = 0, at = 0; r < size; at += counts[r], ++r) {
      counts[r] = static_cast<int>(sizes[r]);
      displs[r] = at;
    }
    std::string joined(total, '\0');
    MPI_Iallgatherv(mine.data(), counts[rank], MPI_BYTE, joined.data(), counts.data(),
                    displs.data(), MPI_BYTE, comm, &req);
    waitQuietly(req);
    for (int r = 0; r < size; ++r) all[r] = joined.substr(displs[r], counts[r]);
    return all;
  }
  for (int r = 0; r < size; ++r) {  // more than an int counts: one broadcast per rank, in pieces
    if (sizes[r] == 0) continue;
    if (r == rank) all[r] = mine;
    broadcast(all[r], r, sizes[r], comm);
  }
  return all;
}

void pack(std::string& out, const PackedUnit& u) {
  const std::int64_t k = static_cast<std::int64_t>(u.k);
  const std::uint64_t n = u.bytes.size();
  out.append(reinterpret_cast<const char*>(&k), sizeof k);
  out.append(reinterpret_cast<const char*>(&u.seconds), sizeof u.seconds);
  out.append(reinterpret_cast<const char*>(&u.cpu_seconds), sizeof u.cpu_seconds);
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out += u.bytes;
}
std::vector<PackedUnit> unpack(const std::string& in) {
  std::vector<PackedUnit> out;
  std::size_t at = 0;
  while (at < in.size()) {
    std::int64_t k;
    double s, c;
    std::uint64_t n;
    std::memcpy(&k, in.data() + at, sizeof k);
    std::memcpy(&s, in.data() + at + 8, sizeof s);
    std::memcpy(&c, in.data() + at + 16, sizeof c);
    std::memcpy(&n, in.data() + at + 24, sizeof n);
    out.push_back({static_cast<std::size_t>(k), s, c, in.substr(at + 32, n)});
    at += 32 + n;
  }
  return out;
}

}  // namespace armstudy::mpi

#endif  // ARMSTUDY_MPI
