#pragma once
// The base of the runners that run shared loops only: the runner a rank group's programs see
// (study/distributed.cpp) and the runner an interleaved program sees (study/interleave.cpp).
#include <string>
#include <utility>

#include "common/errors.hpp"
#include "study/unit_runner.hpp"

namespace armstudy {

class SharedLoopRunner : public UnitRunner {
 public:
  // `outer`: the runner whose local() work nested in a unit uses (null: this one); `who` names the
  // runner in the check that no unit batch reaches it ("a rank group").
  SharedLoopRunner(const CheckpointStore& store, const UnitRunner* outer, std::string who)
      : UnitRunner(store, 1, UnitTimeRecord{}), outer_(outer), who_(std::move(who)) {}
  long run(const UnitBatch&) const override {
    ARMSTUDY_CHECK(false, who_ + " runs shared loops only, no unit batches");
    return 0;
  }
  const UnitRunner& local() const override { return outer_ ? outer_->local() : *this; }

 private:
  const UnitRunner* outer_;
  std::string who_;
};

}  // namespace armstudy
