#pragma once
// The measurement kinds of model versus measurement (docs/calibration.md): `drive` (one joint
// drive on a test bed), `tcp` (measured TCP poses) and `trajectory` (joint efforts or currents
// along a trajectory). A kind's name is parsed once where the user gives it (a study's `kind`
// key, the CLI's --kind, Python's kind argument) into a Kind; every later step asks that object:
// its data reader, its problem for the one engine (arm_calibration.hpp), the options it needs and
// what a study summary shows of its fit.
#include <memory>
#include <string>
#include <vector>

#include "calibration/arm_calibration.hpp"
#include "calibration/drive_calibration.hpp"
#include "calibration/tcp_calibration.hpp"
#include "calibration/trajectory_calibration.hpp"
#include "common/defaults.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

enum class KindId { drive, tcp, trajectory };

// What shapes a kind's problem besides its data: the drive kind's measured joint and the bins of
// its speed x |load| residual grid (the other kinds ignore them).
struct ProblemOptions {
  std::string joint;
  int speed_bins = defaults::kSpeedBins;
  int load_bins = defaults::kLoadBins;
};

class Kind;

// Measurement data of one kind, read for one design; exactly one pointer is set.
struct KindData {
  const Kind* kind = nullptr;
  std::shared_ptr<const DriveData> drive;
  std::shared_ptr<const TcpData> tcp;
  std::shared_ptr<const TrajectoryData> trajectory;
  const std::string& hash() const;
};

class Kind {
 public:
  virtual ~Kind() = default;
  virtual KindId id() const = 0;
  virtual const char* name() const = 0;
  // The drive kind measures the one drive named by ProblemOptions::joint; the others every joint.
  virtual bool measuresOneDrive() const { return false; }
  // Whether the data may come from a robot's own joint logs (a study's [calibration.measured]).
  virtual bool readsJointLogs() const { return false; }
  // Reads a data file for the design; InputError naming the file, line and column (the drive
  // kind first checks that the design has a drive for options.joint).
  virtual KindData read(const std::string& path, const Model& model,
                        const ProblemOptions& options) const = 0;
  // The kind's problem for the engine.
  virtual std::unique_ptr<ArmProblem> problem(const Model& model, const KindData& data,
                                              const ProblemOptions& options) const = 0;
  // The effects a study summary lists with their added and significant flags: the problem's
  // candidate instances, or for the drive kind every drive effect of the catalogue.
  virtual std::vector<std::string> summaryEffects(const ArmProblem& problem) const;
  // The RMSE of a fit over all rows that a study summary shows (fit units).
  virtual double summaryRmse(const ArmFit& fit) const { return fit.train_rmse; }
  // Whether the remainders the fit leaves become warnings of the study.
  virtual bool remaindersWarn() const { return true; }
  // The options of `armstudy synth` that set the size of the data it writes.
  virtual const char* synthSizeOptions() const = 0;
};

// Every kind, in the order the help texts list them.
const std::vector<const Kind*>& kinds();
// The kind of a name; nullptr when there is none.
const Kind* findKind(const std::string& name);
// "drive, tcp, trajectory" (the separator before the last name is `last`, e.g. " or ").
std::string kindNames(const std::string& last = ", ");
// The kind's data, for a trajectory kind read from a robot's joint logs.
KindData trajectoryKindData(TrajectoryData data);

// The fit a study summary takes as the model before the requested effects: the design
// with the effects every fit adds first (ArmProblem::added_first; the drive kind's refit of its
// own friction terms), else the design as is; and the effects added after them.
const ArmFit& baseFit(const ArmDiagnosis& diagnosis, const ArmProblem& problem);
std::vector<std::string> addedAfterBase(const ArmDiagnosis& diagnosis, const ArmProblem& problem);

}  // namespace armstudy::calibration
