#pragma once
// The drive kind's compare and fit through the one engine, as `armstudy compare|fit --drive` runs
// them (measurement_kind.hpp), with the views the drive tests read.
#include <memory>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "calibration/drive_calibration.hpp"
#include "calibration/measurement_kind.hpp"
#include "drive/friction.hpp"

namespace armstudy::calibration::drive_test {

struct DriveFit {
  std::shared_ptr<const ArmProblem> problem;
  ArmDiagnosis d;
  std::vector<std::string> added;  // the effects added after the refit of the design's own terms
  const ArmFit& base() const { return baseFit(d, *problem); }  // the refit (else as designed)
  double rmseBefore() const { return base().heldout_rmse; }
};

inline DriveFit driveFit(const Model& m, const std::string& joint, const DriveData& data,
                         bool auto_add, bool compare_only = false) {
  DriveFit f;
  f.problem = makeDriveProblem(m, joint, data);
  ArmFitOptions o;
  o.auto_add = auto_add;
  f.d = compare_only ? compareArm(*f.problem, o) : diagnoseArm(*f.problem, o);
  f.added = addedAfterBase(f.d, *f.problem);
  return f;
}

inline std::vector<std::string> names(const std::vector<drive::Effect>& effects) {
  std::vector<std::string> out;
  for (drive::Effect e : effects) out.push_back(drive::toString(e));
  return out;
}

}  // namespace armstudy::calibration::drive_test
