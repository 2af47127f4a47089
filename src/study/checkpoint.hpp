#pragma once
// Saving completed work as a study goes, so an interrupted run (Ctrl-C, kill, power loss) resumes
// and finishes with exactly the files an uninterrupted run writes (docs/regression.md).
//
// Work is split into independent units (design/variant x grid chunk), each with a stable id. A
// unit's result is saved atomically under <output>/.partial/units/ as soon as it is done. The
// folder is stamped with a fingerprint of everything the results depend on (armstudy version and
// git revision, the study and design file hashes, resolved settings); a resume with a different
// fingerprint starts fresh and says why, never mixing old and new results.
//
// Units are the grain a later multi-process run distributes (docs/architecture.md): every unit is
// a contiguous range of a stage's independent work items (grid lines, pose-list chunks, dexterity
// rows, harvest approaches, holding-grid points) of one design, its result depends on nothing but
// the inputs and the range, and a stage assembles its result from the units in index order, so
// the result is the same whatever order the units finished in.
#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace armstudy {

class CheckpointStore {
 public:
  // Opens (or creates) the store in `output_dir`. `message` receives one line for the user:
  // "resuming: N completed unit(s) found" or "starting fresh because ...", or stays empty when
  // there was nothing to resume.
  CheckpointStore(std::string output_dir, std::string fingerprint, std::string& message);
  // Disabled store: never loads, never saves (for runs that must not touch disk, e.g. tests).
  CheckpointStore();
  // One disabled store for the runners that wrap another and never save (a timed or an
  // interleaved program's runner).
  static const CheckpointStore& disabled();

  bool enabled() const { return !dir_.empty(); }
  // Loads a unit saved by an earlier run with the same fingerprint.
  bool load(const std::string& unit_id, std::string& bytes) const;
  // Saves a completed unit (atomic). Thread-safe: distinct units may be saved concurrently.
  // Test hook, not a user option: with ARMSTUDY_TEST_ABORT_AFTER_UNITS=N in the environment, the
  // process kills itself with SIGKILL right after this store saved its N-th unit, so the
  // kill/resume tests interrupt a run at a chosen unit instead of racing a kill against it.
  void save(const std::string& unit_id, const std::string& bytes) const;
  int completedUnits() const { return completed_; }
  // Removes the unit files this store saved. In a distributed run every rank removes its own once
  // the manifest is written, so that the files (one per unit: 12 670 for the million-pose sweep
  // with --unit-size 81, about 1.1 s on rank 0 alone here) go in parallel; finish() then takes the
  // rest. Thread-safe with respect to nothing: call it after the stages.
  void removeSaved();
  // Removes the store after the final result files and manifest are written.
  void finish();

  static bool hasPartialRun(const std::string& output_dir);

 private:
  std::string unitPath(const std::string& unit_id) const;
  std::string dir_;
  int completed_ = 0;
  std::size_t abort_after_units_ = 0;  // the test hook of save(); 0: off
  mutable std::mutex saved_mutex_;
  mutable std::vector<std::string> saved_;  // the unit files save() wrote
};

// A contiguous range [begin, end) of work items.
struct ItemRange {
  long begin = 0, end = 0;
  long size() const { return end - begin; }
  // "<begin>-<end>", for unit ids.
  std::string text() const { return std::to_string(begin) + "-" + std::to_string(end); }
};

// Splits items [0, count) into consecutive ranges of `per_range` items (the last may be shorter).
// per_range < 1 counts as 1; count 0 gives no ranges.
std::vector<ItemRange> splitRange(long count, long per_range);

// Completion of ranges whose items are processed in any order by many threads: itemDone(k)
// returns true for exactly one call per range, the one that completes it. That caller sees every
// write the other items' threads made before their itemDone calls (acquire-release), so it may
// read the whole range's results, e.g. to save them.
class RangeCountdown {
 public:
  explicit RangeCountdown(const std::vector<ItemRange>& ranges);
  bool itemDone(std::size_t range);

 private:
  std::unique_ptr<std::atomic<long>[]> left_;
};

// Binary encoding of unit results: a magic string naming the format and its version (bump it
// whenever a unit's layout changes; a unit of another format is not loaded but solved again),
// then values in native byte order (a store is only read back by the same armstudy revision: the
// fingerprint holds it). Values go in bit for bit, so a loaded unit equals the solved one.
class UnitWriter {
 public:
  explicit UnitWriter(std::string_view magic) : bytes_(magic) {}
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void putVector(const std::vector<T>& v) {
    static_assert(std::is_arithmetic_v<T>);
    put<std::uint64_t>(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void putString(const std::string& s);
  // Any Eigen vector or matrix (fixed or dynamic size) of doubles.
  template <class Derived>
  void putMatrix(const Eigen::DenseBase<Derived>& m) {
    put<std::int64_t>(m.rows());
    put<std::int64_t>(m.cols());
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      for (Eigen::Index r = 0; r < m.rows(); ++r) put<double>(m(r, c));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

// Reads what UnitWriter wrote (`bytes` must outlive the reader). A wrong magic, a short buffer or a
// size mismatch makes ok() false (and every later read a no-op); finished() also requires that
// every byte was read.
class UnitReader {
 public:
  // Reads `bytes` in place: they must outlive the reader (binding a temporary is refused).
  UnitReader(const std::string& bytes, std::string_view magic);
  UnitReader(std::string&&, std::string_view) = delete;
  bool ok() const { return ok_; }
  bool finished() const { return ok_ && pos_ == b_.size(); }
  template <class T>
  T get() {
    static_assert(std::is_arithmetic_v<T> || std::is_enum_v<T>);
    T v{};
    if (take(sizeof v)) std::memcpy(&v, b_.data() + pos_ - sizeof v, sizeof v);
    return v;
  }
  template <class T>
  void getVector(std::vector<T>& v) {
    static_assert(std::is_arithmetic_v<T>);
    const auto n = get<std::uint64_t>();
    if (!ok_ || n > (b_.size() - pos_) / sizeof(T)) {
      ok_ = false;
      return;
    }
    v.resize(n);
    if (take(n * sizeof(T)) && n > 0)
      std::memcpy(v.data(), b_.data() + pos_ - n * sizeof(T), n * sizeof(T));
  }
  std::string getString();
  // Into a fixed- or dynamic-size Eigen object; a fixed size must match.
  template <class Derived>
  void getMatrix(Eigen::PlainObjectBase<Derived>& m) {
    const auto rows = get<std::int64_t>(), cols = get<std::int64_t>();
    if (!ok_ || rows < 0 || cols < 0 || rows > (1 << 30) || cols > (1 << 30) ||
        static_cast<std::uint64_t>(rows * cols) > (b_.size() - pos_) / sizeof(double)) {
      ok_ = false;
      return;
    }
    if ((Derived::RowsAtCompileTime != Eigen::Dynamic && rows != Derived::RowsAtCompileTime) ||
        (Derived::ColsAtCompileTime != Eigen::Dynamic && cols != Derived::ColsAtCompileTime) ||
        (Derived::MaxRowsAtCompileTime != Eigen::Dynamic && rows > Derived::MaxRowsAtCompileTime) ||
        (Derived::MaxColsAtCompileTime != Eigen::Dynamic && cols > Derived::MaxColsAtCompileTime)) {
      ok_ = false;
      return;
    }
    m.resize(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c)
      for (Eigen::Index r = 0; r < rows; ++r) m(r, c) = get<double>();
  }
  void fail() { ok_ = false; }

 private:
  bool take(std::size_t n);
  const std::string& b_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

// One list of a unit's fields for both directions: a function template
//   template <class Io, class T> void fields(Io& io, T& t) { unitValue<std::int32_t>(io, t.k); }
// writes with Io = UnitWriter (T const) and reads with Io = UnitReader, so the layouts cannot
// drift. unitValue: a number or bool as its wire type `Wire` (a bool as std::uint8_t reads back
// as != 0); unitField: a std::vector of numbers, an Eigen object, a string or a list of strings.
template <class Wire, class T>
void unitValue(UnitWriter& w, const T& v) {
  w.put<Wire>(static_cast<Wire>(v));
}
template <class Wire, class T>
void unitValue(UnitReader& r, T& v) {
  v = static_cast<T>(r.get<Wire>());
}
template <class T>
inline constexpr bool kIsStdVector = false;
template <class T>
inline constexpr bool kIsStdVector<std::vector<T>> = true;
template <class T>  // a std::vector of numbers or an Eigen object
void unitField(UnitWriter& w, const T& v) {
  if constexpr (kIsStdVector<T>)
    w.putVector(v);
  else
    w.putMatrix(v);
}
template <class T>
void unitField(UnitReader& r, T& v) {
  if constexpr (kIsStdVector<T>)
    r.getVector(v);
  else
    r.getMatrix(v);
}
inline void unitField(UnitWriter& w, const std::string& s) { w.putString(s); }
inline void unitField(UnitReader& r, std::string& s) { s = r.getString(); }
inline void unitField(UnitWriter& w, const std::vector<std::string>& v) {
  w.put<std::uint64_t>(v.size());
  for (const std::string& s : v) w.putString(s);
}
inline void unitField(UnitReader& r, std::vector<std::string>& v) {
  const auto n = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; r.ok() && k < n; ++k) v.push_back(r.getString());
}
// An enum of `count` values 0 .. count-1; a value out of range fails the reader.
template <class Wire, class Enum>
void unitEnum(UnitWriter& w, const Enum& e, int) {
  w.put<Wire>(static_cast<Wire>(e));
}
template <class Wire, class Enum>
void unitEnum(UnitReader& r, Enum& e, int count) {
  const auto v = r.get<Wire>();
  if (v < 0 || v >= count) r.fail();
  e = static_cast<Enum>(v);
}
// The element count of `v` (the caller then lists each element's fields); the reader makes `v`
// that long, at most `max` (more fails the reader).
template <class T>
void unitCount(UnitWriter& w, const std::vector<T>& v, std::uint64_t) {
  w.put<std::uint64_t>(v.size());
}
template <class T>
void unitCount(UnitReader& r, std::vector<T>& v, std::uint64_t max) {
  const auto n = r.get<std::uint64_t>();
  if (n > max) r.fail();
  v.assign(r.ok() ? n : 0, T{});
}

}  // namespace armstudy
