#pragma once
// The model-versus-measurement engine of every kind (`drive`, `tcp`,
// `trajectory`): a generic problem -- rows of measured channels, a prediction from the design plus
// a set of effect instances with physical parameters -- so that compare, rank, add, the
// diagnosis and the outputs are one code path. Each kind only builds its ArmProblem
// (drive_calibration.hpp, tcp_calibration.hpp, trajectory_calibration.hpp). docs/calibration.md.
//
// Fitting: Gauss-Newton on all rows with forward-model Jacobians by central differences and the
// bounded linear least squares of least_squares.hpp in every step (effects nonlinear in a
// parameter, such as the Stribeck velocity, are profiled on a grid). Held-out scores (k-fold and
// by region) use the linearised refit at the full-data optimum: a fold's parameter change solves
// the bounded least-squares problem of the Jacobian on the training rows (exact for models linear
// in their parameters, first order otherwise). 95 % intervals from the linearised covariance over
// the fitted and the profiled parameters. The solver is benchmarked against Ceres
// (tests/benchmarks/calibration_solver_bench.cpp, docs/calibration.md "Solver").
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "calibration/stats.hpp"
#include "common/defaults.hpp"
#include "model/model.hpp"

namespace armstudy::calibration {

struct FittedParameter {
  std::string key;
  std::string unit;
  double value = 0;
  double ci_low = 0, ci_high = 0;  // 95 % interval (linearised, inflated for correlated samples)
  bool at_bound = false;
};

struct ArmParam {
  std::string key;   // e.g. "offset", "mass", "coulomb"
  std::string unit;  // SI unit text
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double typical = 0;  // magnitude `armstudy synth` hides by default
  double step = 1e-6;  // central-difference step (SI)
  // The fit finds a change x to the design; reports show design + x. The drive kind sets the
  // design's own value (its parameters are reported as absolute friction values, thesis Table 4.4);
  // the tcp and trajectory kinds report the change itself (0 here).
  double design = 0;
  // Non-empty: the lower bound is the physically possible limit ("a mass is above zero", "friction
  // is not negative"): a fit that ends on it is refused with the value it would take without it.
  std::string physical = "";
};

// One candidate effect instance, e.g. "joint_offset.j3", "payload", "j5.stribeck".
struct ArmEffect {
  std::string name;              // instance name (what --add/--hide take)
  std::string effect;            // catalogue name, e.g. "joint_offset"
  std::string joint;             // joint it belongs to ("" for global effects)
  std::string pattern;           // the residual pattern it explains
  std::vector<ArmParam> params;  // fitted linearly (Gauss-Newton)
  ArmParam profile;              // a nonlinear parameter profiled on profile_grid (if not empty)
  std::vector<double> profile_grid;
  // A rigid body whose params are the ten standard inertial parameters (m, m c, I about the
  // frame's origin: xx yy zz xy xz yz) added to body_design: the sum must have a positive
  // semidefinite pseudo-inertia (Wensing et al. 2017), else the candidate is refused.
  bool rigid_body = false;
  std::array<double, 10> body_design{};
  bool hasProfile() const { return !profile_grid.empty(); }
};

// The instance "<effect>.<joint>[.<suffix>]" of a per-joint effect (parameters still to set).
inline ArmEffect jointEffect(const std::string& effect, const std::string& joint,
                             std::string pattern, const std::string& suffix = "") {
  ArmEffect e;
  e.name = effect + "." + joint + (suffix.empty() ? "" : "." + suffix);
  e.effect = effect;
  e.joint = joint;
  e.pattern = std::move(pattern);
  return e;
}

// The value of one switched-on effect: parameters (deltas to the design, SI) and profiled value.
struct EffectValue {
  int effect = 0;  // index into ArmProblem::catalogue
  Eigen::VectorXd x;
  double profile = 0;
};
using EffectValues = std::vector<EffectValue>;

struct BinVariable {
  std::string name, unit;
  std::vector<double> values;  // one per row
  bool position = false;       // a joint position: the unexplained-effect search also looks for
                               // residuals periodic in it (cogging, torque ripple)
};

// A measurement data set together with its forward model. Subclasses fill the data members and
// implement predict(); the engine below never looks inside.
class ArmProblem {
 public:
  virtual ~ArmProblem() = default;
  std::string kind;  // the kind's name (measurement_kind.hpp), shown in reports
  std::string design, file, hash;
  std::vector<std::string> channel_names, channel_units;
  // Per channel: the logging resolution of the raw log, before any filter (the grid step of the
  // logged values in channel units; 0 on no grid). Empty: the engine reads it from `measured`.
  std::vector<double> logged_resolution;
  Eigen::VectorXd weight;            // per channel: residual -> fit units (1 unless documented)
  Eigen::MatrixXd measured;          // rows x channels
  std::vector<int> lines;            // file line of each row
  std::vector<ArmEffect> catalogue;  // candidate instances applicable to this design/data
  // Effects every fit adds first, before the requested ones and the ranking, whatever their
  // significance (the drive kind: "refit", its design's own friction terms, thesis Table 4.5).
  std::vector<std::string> added_first;
  std::vector<BinVariable> variables;      // operating variables (plots, joint-space bins)
  std::vector<Eigen::Vector3d> workspace;  // TCP position of each row in W (workspace cells)
  // Channels 0..2 are the TCP position [m] (the tcp kind): the 3-D view shows the length of their
  // residual, one map instead of one per channel.
  bool position_channels = false;
  // A 2-D grid map over two operating variables (the drive kind: signed motor speed x |load|),
  // grid_bins[a] bins on axis a, besides or instead of the 1-D bins of `variables`.
  std::vector<BinVariable> grid;
  std::array<int, 2> grid_bins{0, 0};
  bool bin_variables = true;  // 1-D bins over each operating variable in the residual map
  std::vector<int> regions;   // held-out-by-region partition (ids 0..region_count-1)
  int region_count = 0;
  std::vector<std::string> warnings;
  // Why this data cannot identify the model, as the kind sees it (a joint that never moves); the
  // engine adds "every row is the same operating point" itself (ArmDiagnosis::identifiable).
  std::vector<std::string> unidentifiable;
  std::string fit_unit;  // unit of the overall RMSE
  // Unexplained-effect search: the time of each row (empty: the row order is used) and, when not
  // empty, the name under which the predicted channel value counts as the channel's load.
  std::vector<double> time;
  std::string load_name;

  int rows() const { return static_cast<int>(measured.rows()); }
  int channels() const { return static_cast<int>(measured.cols()); }
  int findEffect(const std::string& name) const;  // -1 when absent
  std::string effectNames() const;                // the catalogue's instance names, ", "-joined
  // Prediction (rows x channels) of the design with the given effects switched on.
  virtual Eigen::MatrixXd predict(const EffectValues& values) const = 0;
  // `model` (the problem's design) with the fitted values applied, each kind where the Model holds
  // them; what it cannot hold is said in notes. calibrated_design.hpp writes it.
  virtual Model calibratedModel(const Model& model, const EffectValues& values,
                                std::vector<std::string>& notes) const = 0;

 protected:
  // Sets kind, design and where the data came from (file, hash, lines, warnings of a *Data).
  template <class Data>
  void setSource(std::string problem_kind, std::string design_name, const Data& data) {
    kind = std::move(problem_kind);
    design = std::move(design_name);
    file = data.file;
    hash = data.hash;
    lines = data.lines;
    warnings = data.warnings;
  }
};

// The cross-validation and effect-selection settings of every kind's fit.
struct CvSettings {
  int folds = defaults::kCvFolds;
  std::uint64_t seed = defaults::kCvSeed;
  double significance_z = defaults::kSignificanceZ;
  double min_relative_improvement = defaults::kMinRelativeImprovement;
  bool auto_add = false;  // add the best significant effect until none is left
  // "" when valid; `bins_ok`: the kind's residual-map bin counts are within binsOk's range.
  std::string validate(bool bins_ok) const;
  // A residual-map bin count within 1..defaults::kMaxResidualBins.
  static bool binsOk(int bins) { return bins >= 1 && bins <= defaults::kMaxResidualBins; }
};

struct ArmFitOptions : CvSettings {
  int variable_bins = defaults::kArmVariableBins;
  int workspace_bins = defaults::kArmWorkspaceBins;
  std::vector<std::string> add;  // effect instances to add, in this order (after added_first)
  std::string validate() const {
    return CvSettings::validate(binsOk(variable_bins) && binsOk(workspace_bins));
  }
};

struct ArmFit {
  std::string label;
  EffectValues values;
  std::vector<std::string> effects;     // instance names
  std::vector<FittedParameter> params;  // key = "<instance>.<param>"
  int n_params = 0;
  double train_rmse = 0, heldout_rmse = 0, region_heldout_rmse = 0;  // fit units
  // Dimensionless: RMS over all channels of residual / that channel's noise estimate.
  // The fit, the ranking and the significance use these per-channel weighted residuals.
  double train_score = 0, heldout_score = 0, region_heldout_score = 0;
  double aic = 0, bic = 0;
  std::vector<ChannelStats> channel_heldout;  // native units
  std::vector<ChannelStats> channel_train;
  std::vector<ChannelStats>
      channel_region_heldout;  // held out by region (time blocks); empty if none
  Eigen::MatrixXd predicted, residual, heldout_residual;  // rows x channels, native units
};

// How one candidate effect scored (every kind's ranking).
struct CandidateScore {
  std::string status = "ok";  // ok | unidentifiable | too_few_rows
  ArmFit fit;
  double improvement = 0, t_statistic = 0;
  bool significant = false;
  std::vector<std::string> warnings;
};

struct ArmCandidate : CandidateScore {
  int effect = 0;
  std::string name;
  // Candidates this one cannot be told apart from with this data (some parameter column in their
  // span), and those whose span contains all of this one's columns.
  std::vector<std::string> indistinguishable;
  std::vector<std::string> contained_in;
};

struct ArmBin {
  std::string space;  // "joint" (a 1-D bin of one operating variable) | "workspace" | "grid"
  std::string
      variable;  // variable name for joint bins, "x,y,z" for workspace cells, "a,b" for grid cells
  std::array<int, 3> index{0, 0, 0};
  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  int n = 0;
  double n_eff = 0;
  std::vector<double> mean;       // per channel, native units
  std::vector<double> threshold;  // per channel
  bool flagged = false;
};

struct ArmResidualMap {
  std::vector<ArmBin> bins;
  double rho = 0, z = 0;
  std::array<int, 3> ws_dims{0, 0, 0};
  std::array<double, 3> ws_origin{0, 0, 0}, ws_cell{0, 0, 0};  // lower corner, cell size [m]
  int flagged() const;
};

// How a residual pattern was found: binned means of a channel against a variable, or a periodic
// residual against a joint position (periodogram). toString gives the name reports write.
enum class PatternKind { binned_means, periodic };
const char* toString(PatternKind kind);

// A pattern in the final model's residuals that no effect of the catalogue explains:
// binned means of one channel against one operating variable, or a periodic residual against a
// joint position (periodogram). Significance is family-wise 5 % over all tests (Bonferroni).
struct ArmPattern {
  std::string channel;   // channel name, e.g. "tau3"
  std::string variable;  // "q3", "qd3", "sign(qd3)", "t", "row", the load name
  std::string unit;      // unit of the variable
  PatternKind kind = PatternKind::binned_means;
  double statistic =
      0;  // binned: largest |bin mean| / its standard error; periodic: chi^2(2) power
  double threshold = 0;  // of the statistic (Bonferroni)
  bool significant = false;
  double explained = 0;  // fraction of the channel's residual sum of squares it explains
  double sum_squares =
      0;  // the part it explains, in squared noise units (comparable between models)
  double period = 0, amplitude = 0;  // periodic: period [variable unit], amplitude [channel unit]
  double peak_mean = 0, peak_lo = 0, peak_hi = 0;  // binned: largest bin mean and its range
  std::string description;
};

// What stands in a channel after the last effect: the strongest significant pattern of its final
// residuals, with its size (RMS of the pattern's part, channel unit), its share of the channel's
// final held-out mean square and of the design's, and the variable it follows. `explained_by_
// catalogue`: added effects halved the channel's held-out RMSE (the remainder is what they leave,
// not an effect outside the catalogue).
struct ArmRemainder {
  std::string channel, unit, variable, description;
  double rms = 0, share_final = 0, share_design = 0;
  double rmse_design = 0, rmse_final = 0;  // the channel's held-out RMSE before and after
  bool explained_by_catalogue = false;
  std::string text() const;  // one sentence, for warnings and answers
};

struct ArmDiagnosis {
  std::string kind, design, file;
  std::vector<std::string> warnings;
  double noise_estimate = 0;          // fit units
  std::vector<double> channel_noise;  // native units; residual weights are 1 / channel_noise
  // Per channel: the logging resolution seen in the data (the grid step its values lie on; 0 when
  // they lie on none) and whether the channel is at that floor (its residual as designed within
  // kFloorSteps steps): such a channel is not identifiable from these logs, no effect is added
  // for it.
  std::vector<double> channel_resolution;
  std::vector<char> channel_at_floor;
  Eigen::MatrixXd
      saturated_residual;  // of the most flexible model (noise estimate); empty if too few rows
  double noise_rho = 0;
  ArmFit as_designed;
  ArmResidualMap as_designed_map;
  std::vector<ArmCandidate>
      ranking;  // for the design as is (plus effects added by --add before it)
  bool missing_effect_found = false;
  std::string verdict;  // "missing effect: X [(cannot be told apart from ...)]",
                        // "missing effects: X, Y" (--auto added several),
                        // "unexplained effect: ..." or "no significant missing effect"
  std::vector<ArmFit> ladder;
  std::vector<std::string> added;
  ArmFit final_fit;
  ArmResidualMap final_map;
  // Unexplained-effect search on the final model's residuals, ranked (significant first, then by
  // the fraction of the residual they explain); unexplained_found when the strongest pattern in a
  // channel above the logging resolution is significant and no catalogue effect is left that would
  // explain it.
  std::vector<ArmPattern> patterns;
  bool unexplained_found = false;
  std::vector<ArmRemainder> remainders;  // one per channel with a significant pattern left
  double rmse_before = 0, rmse_after = 0;
  // Empty when the data can identify the model; otherwise why not (every row the same operating
  // point, a joint that never moves, nothing to fit): said plainly, and no calibrated design.
  std::string identifiable;
};

// Compare only: the design as is, noise estimate, residual map.
ArmDiagnosis compareArm(const ArmProblem& problem, const ArmFitOptions& options);
// Compare, rank the candidates, add effects as the options ask.
ArmDiagnosis diagnoseArm(const ArmProblem& problem, const ArmFitOptions& options);

// One set of effects fitted on all rows with the engine's solver (Gauss-Newton, each step the
// bounded linear least squares of least_squares.hpp; an effect whose profile value is NaN is
// profiled on its grid), in the problem's own channel weights. Exposed for benchmarks and tests.
struct SetFit {
  EffectValues values;
  double ssr = 0;  // weighted sum of squared residuals
};
SetFit fitEffects(const ArmProblem& problem, const EffectValues& start);

// Fitted values of an effect instance in a diagnosis' final fit (nullptr when not added).
const EffectValue* findValue(const EffectValues& values, int effect);

// "name" or "name:key=value,..." -> instance + parameter overrides (typical values otherwise).
EffectValue parseHiddenEffect(const ArmProblem& problem, const std::string& spec);

// Savitzky-Golay derivative (docs/calibration.md): local least-squares polynomial of `degree` over
// 2*half_window+1 samples (shifted inside the series at its ends) differentiated at each sample.
// Precondition: t strictly increasing; samples need not be exactly uniform.
std::vector<double> savitzkyGolayDerivative(const std::vector<double>& t,
                                            const std::vector<double>& y, int half_window,
                                            int degree);

// ---- outputs (compare/fit): result.json, residuals.csv, plots/*.svg, history.csv,
// error_ladder.svg, workspace_cells.vti + residual_points.vtp ----
// Which design a report's "before" model is: the design as given (the calibration's starting
// point) or a calibrated copy compared with the data it was calibrated on (its check run).
enum class ShownDesign { as_designed, calibrated_copy };
// The title of the figures of a report's before (after = false) or after model: "before: as
// designed", "calibrated design (check run)", "after: calibrated (+effect, ...)".
std::string armModelTitle(ShownDesign shown, bool after, const ArmDiagnosis& d);

struct ArmReportOptions {
  std::string out_dir;
  std::string command;  // compare | fit
  // Further files of the result (name in the output folder, content), published with it.
  std::vector<std::pair<std::string, std::string>> extra_files = {};
  // False inside a study run, whose output folder is locked already (no `<out_dir>.lock` is left
  // among its results).
  bool lock = true;
  ShownDesign shown = ShownDesign::as_designed;
};
struct ArmReportSummary {
  std::vector<std::string> files_written;
  std::string json;
};
ArmReportSummary writeArmReport(const ArmDiagnosis& d, const ArmProblem& problem,
                                const ArmReportOptions& o,
                                const std::string& calibrated_design_path);

// Which design design text is: a calibrated copy (its first line is the calibrated design writer's
// header, calibrated_design.hpp) or the design as given.
ShownDesign shownDesign(const std::string& text);

}  // namespace armstudy::calibration
