#include "study/interleave.hpp"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string_view>
#include <thread>

#include "common/errors.hpp"
#include "study/checkpoint.hpp"
#include "study/shared_loop_runner.hpp"

namespace armstudy {

namespace {

constexpr std::string_view kCombinedMagic = "armstudy-interleaved-1";

// Where the programs meet: each program's pending loop, the step counter that releases them. The
// programs wake the runner's thread (`arrived`) and it wakes each program it releases (`go[p]`):
// one condition variable for all would wake every waiting program at every arrival.
struct Meeting {
  std::mutex m;
  std::condition_variable arrived;
  std::vector<std::unique_ptr<std::condition_variable>> go;  // per program
  std::vector<const SharedLoop*> pending;  // per program: the loop it waits in, or null
  std::vector<char> ended;                 // per program: returned or threw
  std::vector<long> released;              // per program: loops completed so far
  bool stopping = false;                   // the combined loop failed: programs stop
};

// The runner a program sees: its shared loops wait for the others'.
class MeetingRunner final : public SharedLoopRunner {
 public:
  MeetingRunner(Meeting& meet, std::size_t index, const UnitRunner* outer)
      : SharedLoopRunner(CheckpointStore::disabled(), outer, "an interleaved program"),
        meet_(meet),
        index_(index) {}
  void share(const SharedLoop& loop) const override {
    std::unique_lock<std::mutex> lk(meet_.m);
    if (meet_.stopping) throw Cancelled();
    const long before = meet_.released[index_];
    meet_.pending[index_] = &loop;
    meet_.arrived.notify_one();
    meet_.go[index_]->wait(lk, [&] { return meet_.released[index_] != before || meet_.stopping; });
    if (meet_.released[index_] == before) throw Cancelled();
  }

  // Thrown in a program when the combined loop failed (the failure itself is rethrown).
  struct Cancelled {};

 private:
  Meeting& meet_;
  std::size_t index_;
};

// The pieces of a combined chunk that fall into each program's loop (local item ranges).
struct Piece {
  std::size_t loop = 0;  // index into the step's loops
  SharedLoop::Chunk chunk;
};

class Combined {
 public:
  // programs[j]: the index of the program whose loop loops[j] is (names its chunks' part).
  Combined(std::vector<const SharedLoop*> loops, const std::vector<std::size_t>& programs)
      : loops_(std::move(loops)) {
    // Each program's loop keeps its own chunks (a combined chunk never spans two programs).
    long off = 0;
    for (std::size_t j = 0; j < loops_.size(); ++j) {
      offsets_.push_back(off);
      for (const ItemRange& r : loops_[j]->chunks()) {
        loop_.ends.push_back(off + r.end);
        part_.push_back(programs[j]);
      }
      off += loops_[j]->items;
    }
    loop_.part = [this](std::size_t k) { return part_[k]; };
    loop_.id = "interleaved/" + std::to_string(loops_.size()) + "/" + loops_.front()->id;
    loop_.items = off;
    loop_.compute = [this](const std::vector<SharedLoop::Chunk>& mine) {
      const auto split = pieces(mine);
      for (std::size_t j = 0; j < loops_.size(); ++j)
        if (!split[j].empty()) loops_[j]->compute(split[j]);
    };
    loop_.finish = [this](const std::vector<SharedLoop::Chunk>& mine) {
      const auto split = pieces(mine);
      for (std::size_t j = 0; j < loops_.size(); ++j)
        if (loops_[j]->finish) loops_[j]->finish(split[j]);
    };
    // The pieces with something to apply, each as (loop index, bytes); empty when none has.
    loop_.pack = [this](std::size_t k, const ItemRange& r) {
      UnitWriter w(kCombinedMagic);
      bool any = false;
      for (const Piece& p : piecesOf(k, r)) {
        const std::string part = loops_[p.loop]->pack(p.chunk.first, p.chunk.second);
        if (part.empty()) continue;
        w.put<std::uint64_t>(p.loop);
        w.putString(part);
        any = true;
      }
      return any ? w.bytes() : std::string();
    };
    loop_.unpack = [this](std::size_t k, const ItemRange& r, const std::string& bytes) {
      if (bytes.empty()) return;
      const std::vector<Piece> pieces = piecesOf(k, r);
      UnitReader rd(bytes, kCombinedMagic);
      std::size_t next = 0;
      while (rd.ok() && !rd.finished()) {
        const auto j = rd.get<std::uint64_t>();
        const std::string part = rd.getString();
        while (next < pieces.size() && pieces[next].loop != j) ++next;
        ARMSTUDY_CHECK(rd.ok() && next < pieces.size(),
                       "an interleaved step's chunk arrives whole");
        loops_[j]->unpack(pieces[next].chunk.first, pieces[next].chunk.second, part);
        ++next;
      }
      ARMSTUDY_CHECK(rd.finished(), "an interleaved step's chunk arrives whole");
    };
  }
  const SharedLoop& loop() const { return loop_; }

 private:
  // Combined chunk k (items r) as pieces of the programs' loops; each keeps the id k.
  std::vector<Piece> piecesOf(std::size_t k, const ItemRange& r) const {
    std::vector<Piece> out;
    for (std::size_t j = 0; j < loops_.size(); ++j) {
      const long b = std::max(r.begin, offsets_[j]),
                 e = std::min(r.end, offsets_[j] + loops_[j]->items);
      if (b < e) out.push_back({j, {k, ItemRange{b - offsets_[j], e - offsets_[j]}}});
    }
    return out;
  }
  std::vector<std::vector<SharedLoop::Chunk>> pieces(
      const std::vector<SharedLoop::Chunk>& mine) const {
    std::vector<std::vector<SharedLoop::Chunk>> split(loops_.size());
    for (const SharedLoop::Chunk& c : mine)
      for (const Piece& p : piecesOf(c.first, c.second)) split[p.loop].push_back(p.chunk);
    return split;
  }

  std::vector<const SharedLoop*> loops_;
  std::vector<long> offsets_;
  std::vector<std::size_t> part_;  // per combined chunk: its program
  SharedLoop loop_;
};

}  // namespace

void runInterleaved(const UnitRunner* runner, const std::vector<InterleavedProgram>& programs,
                    const ProgramResults* results) {
  const std::size_t n = programs.size();
  if (n == 0) return;
  if (runner && results) {
    std::vector<double> weights(n, 1.0);
    if (results->weight)
      for (std::size_t p = 0; p < n; ++p) weights[p] = results->weight(p);
    if (const std::unique_ptr<RankGroups> groups = runner->groups(weights)) {
      std::vector<InterleavedProgram> mine;
      for (std::size_t p = 0; p < n; ++p)
        if (groups->group_of[p] == groups->mine) mine.push_back(programs[p]);
      runInterleaved(&groups->runner(), mine);
      std::vector<std::string> bytes(n);
      for (std::size_t p = 0; p < n; ++p)
        if (groups->sends && groups->group_of[p] == groups->mine) bytes[p] = results->pack(p);
      const std::vector<std::string> all = groups->exchange(bytes);
      for (std::size_t p = 0; p < n; ++p)
        if (groups->group_of[p] != groups->mine) results->unpack(p, all[p]);
      return;
    }
  }
  Meeting meet;
  meet.pending.assign(n, nullptr);
  meet.ended.assign(n, 0);
  meet.released.assign(n, 0);
  for (std::size_t p = 0; p < n; ++p)
    meet.go.push_back(std::make_unique<std::condition_variable>());
  std::vector<std::exception_ptr> errors(n);
  std::vector<std::unique_ptr<MeetingRunner>> runners;
  for (std::size_t p = 0; p < n; ++p)
    runners.push_back(std::make_unique<MeetingRunner>(meet, p, runner));
  std::vector<std::thread> threads;
  for (std::size_t p = 0; p < n; ++p)
    threads.emplace_back([&, p] {
      try {
        programs[p](runners[p].get());
      } catch (const MeetingRunner::Cancelled&) {
      } catch (...) {
        errors[p] = std::current_exception();
      }
      std::lock_guard<std::mutex> g(meet.m);
      meet.ended[p] = 1;
      meet.arrived.notify_one();
    });
  std::exception_ptr failure;
  for (;;) {
    std::vector<std::size_t> at;  // programs waiting in a loop, in program order
    {
      std::unique_lock<std::mutex> lk(meet.m);
      meet.arrived.wait(lk, [&] {
        for (std::size_t p = 0; p < n; ++p)
          if (!meet.ended[p] && !meet.pending[p]) return false;
        return true;
      });
      for (std::size_t p = 0; p < n; ++p)
        if (meet.pending[p]) at.push_back(p);
    }
    if (at.empty()) break;
    std::vector<const SharedLoop*> loops;
    for (std::size_t p : at) loops.push_back(meet.pending[p]);
    try {
      if (n ==
          1) {  // (with several programs, a last one's loops stay combined: their chunks name it)
        runSharedLoop(runner, *loops.front());
      } else {
        const Combined combined(loops, at);
        runSharedLoop(runner, combined.loop());
      }
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard<std::mutex> g(meet.m);
    for (std::size_t p : at) meet.pending[p] = nullptr;
    if (failure) {
      meet.stopping = true;
    } else {
      for (std::size_t p : at) ++meet.released[p];
    }
    if (failure) {
      for (const auto& go : meet.go) go->notify_one();  // every program still running stops
    } else {
      for (std::size_t p : at) meet.go[p]->notify_one();
    }
    if (failure) break;
  }
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace armstudy
