#include "calibration/measurement_kind.hpp"

#include <algorithm>

#include "common/errors.hpp"
#include "drive/friction.hpp"

namespace armstudy::calibration {

namespace {

class DriveKind : public Kind {
 public:
  KindId id() const override { return KindId::drive; }
  const char* name() const override { return "drive"; }
  bool measuresOneDrive() const override { return true; }
  KindData read(const std::string& path, const Model& model,
                const ProblemOptions& o) const override {
    requireDrive(model, o.joint);
    KindData d;
    d.kind = this;
    d.drive = std::make_shared<const DriveData>(readDriveData(path));
    return d;
  }
  std::unique_ptr<ArmProblem> problem(const Model& model, const KindData& data,
                                      const ProblemOptions& o) const override {
    ARMSTUDY_CHECK(data.drive != nullptr, "drive data for the drive kind");
    return makeDriveProblem(model, o.joint, *data.drive, o.speed_bins, o.load_bins);
  }
  std::vector<std::string> summaryEffects(const ArmProblem&) const override {
    std::vector<std::string> names;
    for (const drive::EffectDeclaration& d : drive::effectDeclarations()) names.push_back(d.name);
    return names;
  }
  // The current channel's RMSE (the problem's one channel).
  double summaryRmse(const ArmFit& fit) const override { return fit.channel_train.at(0).rmse; }
  bool remaindersWarn() const override { return false; }
  const char* synthSizeOptions() const override { return "--series, --speeds, --loads"; }
};

class TcpKind : public Kind {
 public:
  KindId id() const override { return KindId::tcp; }
  const char* name() const override { return "tcp"; }
  KindData read(const std::string& path, const Model& model, const ProblemOptions&) const override {
    KindData d;
    d.kind = this;
    d.tcp = std::make_shared<const TcpData>(readTcpData(path, model));
    return d;
  }
  std::unique_ptr<ArmProblem> problem(const Model& model, const KindData& data,
                                      const ProblemOptions&) const override {
    ARMSTUDY_CHECK(data.tcp != nullptr, "tcp data for the tcp kind");
    return makeTcpProblem(model, *data.tcp);
  }
  const char* synthSizeOptions() const override { return "--rows"; }
};

class TrajectoryKind : public Kind {
 public:
  KindId id() const override { return KindId::trajectory; }
  const char* name() const override { return "trajectory"; }
  bool readsJointLogs() const override { return true; }
  KindData read(const std::string& path, const Model& model, const ProblemOptions&) const override {
    return trajectoryKindData(readTrajectoryData(path, model));
  }
  std::unique_ptr<ArmProblem> problem(const Model& model, const KindData& data,
                                      const ProblemOptions&) const override {
    ARMSTUDY_CHECK(data.trajectory != nullptr, "trajectory data for the trajectory kind");
    return makeTrajectoryProblem(model, *data.trajectory);
  }
  const char* synthSizeOptions() const override { return "--duration, --rate"; }
};

const DriveKind kDrive;
const TcpKind kTcp;
const TrajectoryKind kTrajectory;

// The number of leading added effects that the problem adds first.
std::size_t baseSteps(const ArmDiagnosis& d, const ArmProblem& P) {
  std::size_t k = 0;
  while (k < d.added.size() && k < P.added_first.size() && d.added[k] == P.added_first[k]) ++k;
  return k;
}

}  // namespace

const std::string& KindData::hash() const {
  if (drive) return drive->hash;
  if (tcp) return tcp->hash;
  ARMSTUDY_CHECK(trajectory != nullptr, "measurement data holds rows of one kind");
  return trajectory->hash;
}

std::vector<std::string> Kind::summaryEffects(const ArmProblem& P) const {
  std::vector<std::string> names;
  for (const ArmEffect& e : P.catalogue) names.push_back(e.name);
  return names;
}

const std::vector<const Kind*>& kinds() {
  static const std::vector<const Kind*> all = {&kDrive, &kTcp, &kTrajectory};
  return all;
}

const Kind* findKind(const std::string& name) {
  for (const Kind* k : kinds())
    if (name == k->name()) return k;
  return nullptr;
}

std::string kindNames(const std::string& last) {
  std::string s;
  const std::vector<const Kind*>& all = kinds();
  for (std::size_t i = 0; i < all.size(); ++i)
    s += (i == 0 ? "" : i + 1 == all.size() ? last : ", ") + std::string(all[i]->name());
  return s;
}

KindData trajectoryKindData(TrajectoryData data) {
  KindData d;
  d.kind = &kTrajectory;
  d.trajectory = std::make_shared<const TrajectoryData>(std::move(data));
  return d;
}

const ArmFit& baseFit(const ArmDiagnosis& d, const ArmProblem& P) {
  const std::size_t k = baseSteps(d, P);
  return k == 0 ? d.as_designed : d.ladder.at(k);
}

std::vector<std::string> addedAfterBase(const ArmDiagnosis& d, const ArmProblem& P) {
  return {d.added.begin() + static_cast<std::ptrdiff_t>(baseSteps(d, P)), d.added.end()};
}

}  // namespace armstudy::calibration
