#include "study/distributed.hpp"

#include <cstdlib>

#include "common/errors.hpp"
#include "study/checkpoint.hpp"

#ifdef ARMSTUDY_MPI
// The C API only (OpenMPI and MPICH would otherwise pull in their deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

#include "study/mpi_transport.hpp"
#include "study/shared_loop_runner.hpp"
#endif

namespace armstudy {

namespace {

class SingleProcess final : public Ranks {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  int firstFailure(bool failed) const override { return failed ? 0 : 1; }
  std::unique_ptr<UnitRunner> unitRunner(const CheckpointStore& store, int threads, bool,
                                         int) const override {
    return std::make_unique<UnitRunner>(store, threads);
  }
  [[noreturn]] void abortJob(int exit_code) const override { std::exit(exit_code); }
};

// True when a launcher started this process as a rank of a job; `size` receives the job size
// when the environment tells it (0 otherwise).
bool startedByLauncher(int& size) {
  size = 0;
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* s = std::getenv(v)) {
      size = std::atoi(s);
      return true;
    }
  for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

const Ranks& singleProcess() {
  static const SingleProcess single;
  return single;
}

#ifndef ARMSTUDY_MPI

bool mpiAvailable() { return false; }

std::unique_ptr<Ranks> joinMpiJob() {
  int size = 0;
  if (startedByLauncher(size) && size > 1)
    throw InputError(
        "", 0, "",
        "started as one of " + std::to_string(size) +
            " MPI ranks, but this armstudy was built without MPI (CMake option ARMSTUDY_MPI; "
            "install libopenmpi-dev and reconfigure); run it without mpirun/srun");
  return nullptr;
}

#else  // ARMSTUDY_MPI

bool mpiAvailable() { return true; }

namespace {

using namespace mpi;
using Clock = std::chrono::steady_clock;

constexpr int kTagRequest = 11;  // worker -> rank 0: units finished since the last request (int64)
constexpr int kTagWork = 12;     // rank 0 -> worker: unit indices (int64), none = the batch is done
// Hand-out chunk: remaining units / (kGuidedFactor x ranks), at least one ("guided"
// self-scheduling: few messages while much is left, single units at the end so the ranks finish
// together).
constexpr long kGuidedFactor = 4;
constexpr double kProgressEverySeconds = 5.0;
// A shared loop (UnitRunner::share) is cut into chunks of SharedLoop::chunk items owned
// round-robin (chunk k by rank k mod size): a loop whose cost sits in a band of neighbouring items
// (the reach search's front) still spreads over the ranks, and a unit-cost record replays the split
// exactly. Each rank computes all its chunks in one call, so the number of chunks costs no set-up.

// The units of one batch still to hand out (rank 0).
class Pool {
 public:
  Pool(std::vector<std::size_t> todo, int ranks, bool single)
      : todo_(std::move(todo)), ranks_(ranks), single_(single) {}
  std::vector<std::size_t> take() {
    std::lock_guard<std::mutex> g(m_);
    const long left = static_cast<long>(todo_.size() - next_);
    const long n = single_ ? std::min(1L, left)
                           : std::min(left, std::max(1L, left / (kGuidedFactor * ranks_)));
    std::vector<std::size_t> out(todo_.begin() + next_, todo_.begin() + next_ + n);
    next_ += n;
    return out;
  }

 private:
  std::mutex m_;
  std::vector<std::size_t> todo_;
  std::size_t next_ = 0;
  int ranks_;
  bool single_;
};

// Progress of the whole job on stderr, from rank 0: one line every few seconds per batch.
class JobProgress {
 public:
  JobProgress(bool enabled, std::string label, long total, int ranks)
      : enabled_(enabled),
        label_(std::move(label)),
        total_(total),
        ranks_(ranks),
        t0_(Clock::now()),
        last_(t0_) {}
  void add(long n) {
    if (!enabled_ || n <= 0) return;
    std::lock_guard<std::mutex> g(m_);
    done_ += n;
    const auto now = Clock::now();
    if (done_ < total_ &&
        std::chrono::duration<double>(now - last_).count() < kProgressEverySeconds)
      return;
    last_ = now;
    const double t = std::chrono::duration<double>(now - t0_).count();
    if (done_ >= total_ && t < kProgressEverySeconds) return;  // short batches stay quiet
    const double eta = done_ > 0 ? t * double(total_ - done_) / double(done_) : 0;
    std::fprintf(
        stderr, "armstudy: %s: %ld/%ld units on %d ranks, %.0f s, %s\n", label_.c_str(), done_,
        total_, ranks_, t,
        done_ >= total_ ? "done" : ("ETA " + std::to_string(long(eta + 0.5)) + " s").c_str());
    std::fflush(stderr);
  }

 private:
  bool enabled_;
  std::string label_;
  long total_, done_ = 0;
  int ranks_;
  Clock::time_point t0_, last_;
  std::mutex m_;
};

// "reach/wall/design/units_0-4" -> "reach/wall/design".
std::string batchLabel(const UnitBatch& b) {
  if (b.ids.empty()) return "batch";
  const std::string& id = b.ids.front();
  const auto slash = id.rfind('/');
  return slash == std::string::npos ? id.substr(0, id.find('-')) : id.substr(0, slash);
}

// A shared loop among the processes of `comm` (this one is `rank` of `size`): the loop's chunks
// (SharedLoop::chunks), owned round-robin (chunk k by rank k mod size); each rank computes its
// chunks in one call and every rank applies the others' results.
void shareOver(const SharedLoop& loop, MPI_Comm comm, int rank, int size) {
  const std::vector<ItemRange> chunks = loop.chunks();
  std::vector<SharedLoop::Chunk> mine;
  for (std::size_t k = static_cast<std::size_t>(rank); k < chunks.size();
       k += static_cast<std::size_t>(size))
    mine.push_back({k, chunks[k]});
  loop.computeAll(mine);
  std::string blob;
  for (const SharedLoop::Chunk& c : mine) {
    std::string bytes = loop.pack(c.first, c.second);
    if (!bytes.empty())
      pack(blob, {c.first, 0.0, 0.0, std::move(bytes)});  // empty: nothing to apply
  }
  const std::vector<std::string> blobs = allGather(blob, rank, size, comm);
  for (int r = 0; r < size; ++r)
    if (r != rank)
      for (const PackedUnit& u : unpack(blobs[r])) loop.unpack(u.k, chunks[u.k], u.bytes);
}

// The runner of one rank group (RankGroups::runner): shared loops among the group's ranks.
class GroupRunner final : public SharedLoopRunner {
 public:
  GroupRunner(const UnitRunner& outer, MPI_Comm comm, int rank, int size)
      : SharedLoopRunner(outer.store(), &outer, "a rank group"),
        comm_(comm),
        rank_(rank),
        size_(size) {}
  void share(const SharedLoop& loop) const override {
    if (size_ == 1 || loop.items <= 0) return UnitRunner::share(loop);
    shareOver(loop, comm_, rank_, size_);
  }

 private:
  MPI_Comm comm_;
  int rank_, size_;
};

// Rank groups (UnitRunner::groups): consecutive ranks per group, one communicator each.
class MpiRankGroups final : public RankGroups {
 public:
  MpiRankGroups(const UnitRunner& outer, const RankGroupPlan& plan, int rank, int size)
      : rank_(rank), size_(size) {
    group_of = plan.group_of;
    int first = 0;
    for (std::size_t j = 0; j < plan.ranks.size(); ++j) {
      if (rank < first + plan.ranks[j]) {
        mine = j;
        break;
      }
      first += plan.ranks[j];
    }
    sends = rank == first;
    MPI_Comm_split(MPI_COMM_WORLD, static_cast<int>(mine), rank, &comm_);
    int grank = 0, gsize = 1;
    MPI_Comm_rank(comm_, &grank);
    MPI_Comm_size(comm_, &gsize);
    runner_ = std::make_unique<GroupRunner>(outer, comm_, grank, gsize);
  }
  ~MpiRankGroups() override {
    runner_.reset();
    MPI_Comm_free(&comm_);
  }
  const UnitRunner& runner() const override { return *runner_; }
  std::vector<std::string> exchange(const std::vector<std::string>& bytes) const override {
    std::string blob;
    if (sends)
      for (std::size_t p = 0; p < bytes.size(); ++p)
        if (group_of[p] == mine) pack(blob, {p, 0.0, 0.0, bytes[p]});
    std::vector<std::string> all(bytes.size());
    for (const std::string& b : allGather(blob, rank_, size_))
      for (PackedUnit& u : unpack(b)) all[u.k] = std::move(u.bytes);
    return all;
  }

 private:
  int rank_, size_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  std::unique_ptr<GroupRunner> runner_;
};

class MpiUnitRunner final : public UnitRunner {
 public:
  MpiUnitRunner(const CheckpointStore& store, int threads, bool progress, int rank, int size,
                int group_ranks)
      : UnitRunner(store, threads),
        progress_(progress),
        rank_(rank),
        size_(size),
        group_ranks_(group_ranks),
        local_(store, threads) {}

  const UnitRunner& local() const override { return local_; }

  long run(const UnitBatch& batch) const override {
    const std::size_t n = batch.ids.size();
    if (!batch.portable) return runEverywhere(batch);

    // A: rank 0 loads what an interrupted run saved and tells the others (bytes included).
    std::vector<char> present(n, 0);
    std::string blob;
    if (rank_ == 0) {
      for (std::size_t k = 0; k < n; ++k) {
        std::string bytes;
        if (store_.load(batch.ids[k], bytes) && batch.load(k, bytes)) {
          present[k] = 1;
          pack(blob, {k, 0.0, 0.0, std::move(bytes)});
        }
      }
    }
    std::uint64_t blob_size = blob.size();
    MPI_Request req;
    MPI_Ibcast(&blob_size, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &req);
    waitQuietly(req);
    std::vector<std::size_t>
        refused;  // units this rank's stage did not take: computed here at the end
    if (blob_size > 0) {
      broadcast(blob, 0, blob_size);
      for (PackedUnit& u : unpack(blob)) {
        present[u.k] = 1;
        if (rank_ != 0 && !batch.load(u.k, u.bytes)) refused.push_back(u.k);
      }
    }
    blob.clear();
    std::vector<std::size_t> todo;
    for (std::size_t k = 0; k < n; ++k)
      if (!present[k]) todo.push_back(k);
    const long resumed = static_cast<long>(n - todo.size());

    // B: the units, handed out by rank 0 on demand; each rank saves what it computes.
    std::vector<PackedUnit> mine;
    std::vector<std::size_t> last_call;
    computeHandedOut(batch, todo, mine, last_call);
    // C and D: every rank receives the units computed elsewhere, the stage takes them.
    takeComputed(batch, todo, mine, last_call, refused);
    return resumed;
  }

 private:
  // B: computes the units rank 0 hands out on demand (rank 0 serves the others from a thread while
  // it computes too); each rank saves what it computes and keeps it in `mine` with its timings;
  // `last_call` is the stage's latest compute call.
  void computeHandedOut(const UnitBatch& batch, const std::vector<std::size_t>& todo,
                        std::vector<PackedUnit>& mine, std::vector<std::size_t>& last_call) const {
    std::mutex mine_m;
    const UnitBatch::Done done = [&](std::size_t k, const std::string& bytes) {
      store_.save(batch.ids[k], bytes);
      std::lock_guard<std::mutex> g(mine_m);
      mine.push_back({k, 0.0, 0.0, bytes});
    };
    auto computeChunk = [&](const std::vector<std::size_t>& chunk) {
      const auto t0 = Clock::now();
      const double c0 = UnitTimeRecord::processCpuSeconds();
      const std::size_t first = mine.size();
      batch.compute(chunk, done);
      const double s =
          std::chrono::duration<double>(Clock::now() - t0).count() / double(chunk.size());
      const double c = (UnitTimeRecord::processCpuSeconds() - c0) / double(chunk.size());
      for (std::size_t i = first; i < mine.size(); ++i) {
        mine[i].seconds = s;
        mine[i].cpu_seconds = c;
      }
      last_call = chunk;
    };
    if (!todo.empty()) {
      if (rank_ == 0) {
        Pool pool(todo, size_, times_.enabled());
        JobProgress progress(progress_, batchLabel(batch), static_cast<long>(todo.size()), size_);
        std::thread server;
        if (size_ > 1) server = std::thread([&] { serve(pool, progress); });
        for (std::vector<std::size_t> chunk = pool.take(); !chunk.empty(); chunk = pool.take()) {
          computeChunk(chunk);
          progress.add(static_cast<long>(chunk.size()));
        }
        if (server.joinable()) server.join();
      } else {
        std::int64_t finished = 0;
        for (;;) {
          MPI_Send(&finished, 1, MPI_INT64_T, 0, kTagRequest, MPI_COMM_WORLD);
          MPI_Status st = probeQuietly(0, kTagWork);
          int count = 0;
          MPI_Get_count(&st, MPI_INT64_T, &count);
          std::vector<std::int64_t> got(count);
          MPI_Recv(got.data(), count, MPI_INT64_T, 0, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          if (got.empty()) break;
          computeChunk(std::vector<std::size_t>(got.begin(), got.end()));
          finished = count;
        }
      }
    }
  }

  // C: every rank receives the units computed elsewhere (sizes first: the ranks still computing
  // are waited for without spinning). D: the stage takes every unit it did not compute in its
  // latest call (UnitBatch); a unit it refuses (never expected for portable units) is computed
  // here once more.
  void takeComputed(const UnitBatch& batch, const std::vector<std::size_t>& todo,
                    const std::vector<PackedUnit>& mine, const std::vector<std::size_t>& last_call,
                    std::vector<std::size_t>& refused) const {
    const std::size_t n = batch.ids.size();
    std::string blob;
    for (const PackedUnit& u : mine) pack(blob, u);
    std::vector<std::string> all(n);
    std::vector<double> seconds(n, 0.0), cpu_seconds(n, 0.0);
    std::vector<int> where(n, -1);
    std::vector<std::string> blobs = allGather(blob, rank_, size_);
    for (int r = 0; r < size_; ++r) {
      for (PackedUnit& u : unpack(blobs[r])) {
        seconds[u.k] = u.seconds;
        cpu_seconds[u.k] = u.cpu_seconds;
        where[u.k] = r;
        all[u.k] = std::move(u.bytes);
      }
    }

    std::vector<char> in_last(n, 0);
    for (std::size_t k : last_call) in_last[k] = 1;
    for (std::size_t k : todo) {
      ARMSTUDY_CHECK(where[k] >= 0, "unit " + batch.ids[k] + " was computed by some rank");
      if (!in_last[k] && !batch.load(k, all[k])) refused.push_back(k);
    }
    if (!refused.empty()) {
      for (std::size_t k : last_call)
        ARMSTUDY_CHECK(batch.load(k, all[k]), "a unit this rank computed loads back");
      std::sort(refused.begin(), refused.end());
      batch.compute(refused, [](std::size_t, const std::string&) {});
    }
    if (rank_ == 0 && times_.enabled()) {
      std::vector<UnitTimeRecord::Line> lines;
      for (std::size_t k : todo)
        lines.push_back(
            {batch.ids[k], seconds[k], cpu_seconds[k], threads_, where[k], all[k].size()});
      times_.append(lines);
    }
  }

  void share(const SharedLoop& loop) const override {
    if (size_ == 1 || loop.items <= 0) return UnitRunner::share(loop);
    shareOver(loop, MPI_COMM_WORLD, rank_, size_);
  }

  std::unique_ptr<RankGroups> groups(const std::vector<double>& weights) const override {
    if (group_ranks_ <= 0) return nullptr;
    const RankGroupPlan plan = planRankGroups(weights, size_, group_ranks_);
    if (plan.ranks.empty()) return nullptr;
    return std::make_unique<MpiRankGroups>(*this, plan, rank_, size_);
  }

  // A batch whose units write files naming the output folder: every rank computes it all in its
  // own folder; only rank 0 uses the store.
  long runEverywhere(const UnitBatch& batch) const {
    if (rank_ == 0) return UnitRunner::run(batch);
    std::vector<std::size_t> all(batch.ids.size());
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = k;
    if (!all.empty()) batch.compute(all, [](std::size_t, const std::string&) {});
    return 0;
  }

  // Rank 0's hand-out thread: answers every worker's request with the next chunk until each has
  // been told that nothing is left. The only thread of rank 0 calling MPI meanwhile.
  void serve(Pool& pool, JobProgress& progress) const {
    int active = size_ - 1;
    while (active > 0) {
      const MPI_Status st = probeQuietly(MPI_ANY_SOURCE, kTagRequest);
      std::int64_t finished = 0;
      MPI_Recv(&finished, 1, MPI_INT64_T, st.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      progress.add(finished);
      const std::vector<std::size_t> chunk = pool.take();
      const std::vector<std::int64_t> msg(chunk.begin(), chunk.end());
      MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_INT64_T, st.MPI_SOURCE, kTagWork,
               MPI_COMM_WORLD);
      if (chunk.empty()) --active;
    }
  }

  bool progress_;
  int rank_, size_;
  int group_ranks_;  // RunOptions::search_group_ranks
  UnitRunner local_;
};

// Rank 0's last words when the launcher stops the job (it sends SIGTERM to every rank when one
// rank died or the job was cancelled): what happened and how to resume. Async-signal-safe.
const char kStoppedMessage[] =
    "armstudy: the MPI job was stopped (a rank died or the job was cancelled); the units completed "
    "so far are "
    "saved in the output folder's .partial/: run the same command again, with any number of ranks, "
    "to resume\n";
extern "C" void onStopped(int sig) {
  const ssize_t ignored = ::write(STDERR_FILENO, kStoppedMessage, sizeof kStoppedMessage - 1);
  (void)ignored;
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

class MpiRanks final : public Ranks {
 public:
  MpiRanks() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    if (provided < MPI_THREAD_SERIALIZED) {
      if (rank_ == 0)
        std::fprintf(
            stderr,
            "armstudy: error: the MPI library offers no MPI_THREAD_SERIALIZED (rank 0 hands out "
            "units from a second thread)\n");
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    if (rank_ == 0 && size_ > 1) {
      struct sigaction sa {};
      sa.sa_handler = onStopped;
      sigemptyset(&sa.sa_mask);
      ::sigaction(SIGTERM, &sa, nullptr);
    }
  }
  ~MpiRanks() override { MPI_Finalize(); }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int firstFailure(bool failed) const override {
    int mine = failed ? rank_ : size_, first = size_;
    MPI_Request req;
    MPI_Iallreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &req);
    waitQuietly(req);
    return first;
  }
  std::unique_ptr<UnitRunner> unitRunner(const CheckpointStore& store, int threads, bool progress,
                                         int group_ranks) const override {
    return std::make_unique<MpiUnitRunner>(store, threads, progress && rank_ == 0, rank_, size_,
                                           group_ranks);
  }
  [[noreturn]] void abortJob(int exit_code) const override {
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::exit(exit_code);
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::unique_ptr<Ranks> joinMpiJob() {
  int size = 0;
  if (!startedByLauncher(size)) return nullptr;
  return std::make_unique<MpiRanks>();
}

#endif  // ARMSTUDY_MPI

}  // namespace armstudy
