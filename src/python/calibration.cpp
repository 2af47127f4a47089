// Model versus measurement (docs/calibration.md) with the engine `armstudy synth|compare|fit` runs:
// synthesize measured TCP poses with hidden effects, compare a design with measurements of any
// kind (the tcp kind also on arrays), fit and rank the missing effects.
#include <pybind11/stl.h>

#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "calibration/arm_calibration.hpp"
#include "calibration/measurement_kind.hpp"
#include "io/files.hpp"
#include "python/bindings.hpp"

namespace armstudy::python {

namespace {

using namespace armstudy::calibration;

py::array_t<double> matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      a.mutable_data(), m.rows(), m.cols()) = m;
  return a;
}

// The data: a CSV path (read as the CLI reads it) or the arrays q (N, dof) and pose (N, 3 or 6).
TcpData tcpData(const Model& m, const py::object& data_, const py::handle& pose) {
  const py::object data = pathLike(data_);
  if (py::isinstance<py::str>(data)) {
    if (!pose.is_none()) throw std::invalid_argument("pose: give it with q arrays, not a file");
    return readTcpData(data.cast<std::string>(), m);
  }
  const Rows q = readRows(data, m.dof(), "q");
  const auto p6 = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
  const long cols = p6 && p6.ndim() == 2 ? static_cast<long>(p6.shape(1)) : 0;
  if (cols != 3 && cols != 6) throw std::invalid_argument("pose: expected shape (N, 3) or (N, 6)");
  const Rows p = readRows(pose, cols, "pose");
  if (p.n != q.n || q.single) throw std::invalid_argument("q and pose: expected N rows each");
  TcpData d;
  d.file = "arrays";
  d.q.resize(q.n, m.dof());
  d.pose.resize(p.n, cols);
  for (long i = 0; i < q.n; ++i) {
    for (int j = 0; j < m.dof(); ++j) d.q(i, j) = q.row(i)[j];
    for (long c = 0; c < cols; ++c) d.pose(i, c) = p.row(i)[c];
    d.lines.push_back(static_cast<int>(i) + 2);  // as the rows of a CSV file under its header
  }
  d.hash = contentHash(tcpDataToCsv(d));
  return d;
}

// A dict of the given items, in their order.
py::dict dictOf(std::initializer_list<std::pair<const char*, py::object>> items) {
  py::dict d;
  for (const auto& [key, value] : items) d[key] = value;
  return d;
}

py::dict fitDict(const ArmFit& f) {
  py::list params;
  for (const FittedParameter& p : f.params)
    params.append(dictOf({{"key", py::cast(p.key)},
                          {"unit", py::cast(p.unit)},
                          {"value", py::cast(p.value)},
                          {"ci_low", py::cast(p.ci_low)},
                          {"ci_high", py::cast(p.ci_high)},
                          {"at_bound", py::cast(p.at_bound)}}));
  return dictOf({{"label", py::cast(f.label)},
                 {"effects", py::cast(f.effects)},
                 {"params", params},
                 {"n_params", py::cast(f.n_params)},
                 {"train_rmse", py::cast(f.train_rmse)},
                 {"heldout_rmse", py::cast(f.heldout_rmse)},
                 {"region_heldout_rmse", py::cast(f.region_heldout_rmse)},
                 {"train_score", py::cast(f.train_score)},
                 {"heldout_score", py::cast(f.heldout_score)},
                 {"aic", py::cast(f.aic)},
                 {"bic", py::cast(f.bic)},
                 {"predicted", matrix(f.predicted)},
                 {"residual", matrix(f.residual)}});
}

py::dict diagnosisDict(const ArmDiagnosis& d, const ArmProblem& P) {
  py::list ladder, ranking, patterns;
  for (const ArmFit& f : d.ladder) ladder.append(fitDict(f));
  for (const ArmCandidate& c : d.ranking)
    ranking.append(dictOf({{"name", py::cast(c.name)},
                           {"status", py::cast(c.status)},
                           {"heldout_rmse", py::cast(c.fit.heldout_rmse)},
                           {"improvement", py::cast(c.improvement)},
                           {"t_statistic", py::cast(c.t_statistic)},
                           {"significant", py::cast(c.significant)},
                           {"indistinguishable", py::cast(c.indistinguishable)},
                           {"warnings", py::cast(c.warnings)}}));
  for (const ArmPattern& p : d.patterns)
    patterns.append(dictOf({{"channel", py::cast(p.channel)},
                            {"variable", py::cast(p.variable)},
                            {"kind", py::cast(toString(p.kind))},
                            {"significant", py::cast(p.significant)},
                            {"explained", py::cast(p.explained)},
                            {"description", py::cast(p.description)}}));
  return dictOf({{"kind", py::cast(d.kind)},
                 {"design", py::cast(d.design)},
                 {"channels", py::cast(P.channel_names)},
                 {"units", py::cast(P.channel_units)},
                 {"fit_unit", py::cast(P.fit_unit)},
                 {"warnings", py::cast(d.warnings)},
                 {"noise_estimate", py::cast(d.noise_estimate)},
                 {"channel_noise", py::cast(d.channel_noise)},
                 {"as_designed", fitDict(d.as_designed)},
                 {"ranking", ranking},
                 {"ladder", ladder},
                 {"added", py::cast(d.added)},
                 {"final", fitDict(d.final_fit)},
                 {"verdict", py::cast(d.verdict)},
                 {"patterns", patterns},
                 {"rmse_before", py::cast(d.rmse_before)},
                 {"rmse_after", py::cast(d.rmse_after)},
                 {"identifiable", py::cast(d.identifiable)},
                 {"measured", matrix(P.measured)}});
}

// The residual-map bin counts within the CLI's bounds (--speed-bins, ...), checked before any
// bins are allocated.
void checkBins(int variable_bins, int workspace_bins, int speed_bins, int load_bins) {
  const std::pair<const char*, int> bins[] = {{"variable_bins", variable_bins},
                                              {"workspace_bins", workspace_bins},
                                              {"speed_bins", speed_bins},
                                              {"load_bins", load_bins}};
  for (const auto& [name, value] : bins) checkArgument(name, value, 1, defaults::kMaxResidualBins);
}

ArmFitOptions fitOptions(int folds, std::uint64_t seed, int variable_bins, int workspace_bins) {
  ArmFitOptions o;
  o.folds = folds;
  o.seed = seed;
  o.variable_bins = variable_bins;
  o.workspace_bins = workspace_bins;
  return o;
}

// The problem of any kind, as `armstudy compare|fit` builds it: tcp from a CSV path or arrays,
// drive (the test bed of `joint`'s drive) and trajectory from their CSV files.
std::unique_ptr<ArmProblem> problem(const Model& m, const std::string& kind_name,
                                    const py::object& data_, const py::handle& pose,
                                    const std::string& joint, int speed_bins, int load_bins) {
  const py::object data = pathLike(data_);
  const Kind* kind = findKind(kind_name);
  if (!kind) throw std::invalid_argument("kind: '" + kind_name + "' is not one of " + kindNames());
  if (kind->id() == KindId::tcp) return makeTcpProblem(m, tcpData(m, data, pose));
  if (!py::isinstance<py::str>(data) || !pose.is_none())
    throw std::invalid_argument("data: the " + kind_name + " kind reads its CSV file (a path)");
  const ProblemOptions po{joint, speed_bins, load_bins};
  return kind->problem(m, kind->read(data.cast<std::string>(), m, po), po);
}

py::dict compare(const Design& design, const py::object& data, const std::string& kind,
                 const py::handle& pose, const std::string& joint, int variable_bins,
                 int workspace_bins, int speed_bins, int load_bins) {
  checkBins(variable_bins, workspace_bins, speed_bins, load_bins);
  const std::unique_ptr<ArmProblem> P =
      problem(*design.model, kind, data, pose, joint, speed_bins, load_bins);
  ArmFitOptions o =
      fitOptions(defaults::kCvFolds, defaults::kCvSeed, variable_bins, workspace_bins);
  if (const std::string error = o.validate(); !error.empty()) throw std::invalid_argument(error);
  ArmDiagnosis diagnosis;
  {
    py::gil_scoped_release release;
    diagnosis = compareArm(*P, o);
  }
  return diagnosisDict(diagnosis, *P);
}

py::dict fit(const Design& design, const py::object& data, const std::string& kind,
             const py::handle& pose, const std::string& joint, const std::vector<std::string>& add,
             bool auto_add, int folds, std::uint64_t seed, int variable_bins, int workspace_bins,
             int speed_bins, int load_bins) {
  checkBins(variable_bins, workspace_bins, speed_bins, load_bins);
  const std::unique_ptr<ArmProblem> P =
      problem(*design.model, kind, data, pose, joint, speed_bins, load_bins);
  ArmFitOptions o = fitOptions(folds, seed, variable_bins, workspace_bins);
  o.auto_add = auto_add;
  for (const std::string& e : add) o.add.push_back(e);
  if (const std::string error = o.validate(); !error.empty()) throw std::invalid_argument(error);
  ArmDiagnosis diagnosis;
  {
    py::gil_scoped_release release;
    diagnosis = diagnoseArm(*P, o);
  }
  return diagnosisDict(diagnosis, *P);
}

py::dict synthesize(const Design& design, int rows, double noise, bool orientation,
                    double noise_angle, const std::vector<std::string>& hidden,
                    std::uint64_t seed) {
  TcpSynthOptions o;
  o.rows = rows;
  o.noise_m = noise;
  o.noise_rad = noise_angle;
  o.orientation = orientation;
  o.hidden = hidden;
  o.seed = seed;
  if (rows < 1) throw std::invalid_argument("rows must be positive");
  const TcpData d = synthesizeTcp(*design.model, o);
  py::dict out;
  out["q"] = matrix(d.q);
  out["pose"] = matrix(d.pose);
  out["csv"] = tcpDataToCsv(d);
  return out;
}

}  // namespace

void bindCalibration(py::module_& m) {
  m.def("synthesize_tcp", &synthesize, py::arg("design"), py::arg("rows") = 60,
        py::arg("noise") = 1e-4, py::arg("orientation") = false, py::arg("noise_angle") = 1e-4,
        py::arg("hidden") = std::vector<std::string>{}, py::arg("seed") = 1,
        R"(Measured TCP poses of the design with hidden effects, as `armstudy synth --kind tcp`
(e.g. hidden=['joint_offset.j3', 'link_length.j4:length=0.002']). Returns q (N, dof), pose
(N, 3 or 6) and the CSV text the CLI writes.)");
  m.def("compare", &compare, py::arg("design"), py::arg("data"), py::arg("kind") = "tcp",
        py::arg("pose") = py::none(), py::arg("joint") = "",
        py::arg("variable_bins") = defaults::kArmVariableBins,
        py::arg("workspace_bins") = defaults::kArmWorkspaceBins,
        py::arg("speed_bins") = defaults::kSpeedBins, py::arg("load_bins") = defaults::kLoadBins,
        R"(The design against measurements, as `armstudy compare`: kind 'tcp' (data: a CSV path, or
the q array (N, dof) with pose (N, 3 or 6)), 'drive' (data: the test-bed CSV of `joint`'s drive)
or 'trajectory' (data: a CSV path). Returns the diagnosis dict (as_designed fit with predicted and
residual arrays, noise estimate, ...).)");
  m.def("fit", &fit, py::arg("design"), py::arg("data"), py::arg("kind") = "tcp",
        py::arg("pose") = py::none(), py::arg("joint") = "",
        py::arg("add") = std::vector<std::string>{}, py::arg("auto") = false,
        py::arg("folds") = defaults::kCvFolds, py::arg("seed") = defaults::kCvSeed,
        py::arg("variable_bins") = defaults::kArmVariableBins,
        py::arg("workspace_bins") = defaults::kArmWorkspaceBins,
        py::arg("speed_bins") = defaults::kSpeedBins, py::arg("load_bins") = defaults::kLoadBins,
        R"(Compare, rank the candidate effects and add them (add=[...] in order, auto=True: the
best significant one until none is left), as `armstudy fit` (data and kind as compare). Returns
the diagnosis: ranking (ranked effects), ladder (the models as effects were added), final
(parameters with 95 % intervals), verdict, rmse_before/after (held out), patterns, ...)");
}

}  // namespace armstudy::python
