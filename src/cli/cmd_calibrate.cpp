// CLI for model versus measurement (docs/calibration.md): compare, fit, synth for the kinds drive
// (one joint drive on a test bed), tcp (measured TCP poses) and trajectory (joint
// efforts/currents).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <sstream>
#include <tuple>

#include "calibration/calibration_run.hpp"
#include "calibration/measurement_kind.hpp"
#include "cli/design_options.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "drive/friction.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::cli {
namespace {

std::vector<std::string> splitList(const std::string& s, char sep = ',') {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, sep);)
    if (!x.empty()) out.push_back(x);
  return out;
}

drive::Effect parseEffectOption(const std::string& name, const std::string& option) {
  return calibration::parseDriveEffect(name, "", 0, option);
}

double parseNumber(const std::string& s, const std::string& option) {
  try {
    std::size_t pos = 0;
    const double v = std::stod(s, &pos);
    if (pos == s.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw InputError("", 0, option, "'" + s + "' is not a number");
}

struct ArmSynthArgs {
  calibration::TcpSynthOptions tcp;
  calibration::TrajectorySynthOptions traj;
  bool no_qdd = false;
};

struct CommonArgs {
  std::string kind = "drive";
  std::string design, joint, data, out;
  int speed_bins = defaults::kSpeedBins, load_bins = defaults::kLoadBins;
  int variable_bins = defaults::kArmVariableBins, workspace_bins = defaults::kArmWorkspaceBins;
  DesignSourceOptions src;  // URDF designs: --base/--tip/--package
};

const char* kKindHelp =
    "Kind of measurement data: drive (CSV speed, load_torque, current[, temperature]; needs "
    "--drive),\n"
    "tcp (CSV q1..qn, x, y, z[, alpha, beta, gamma]: measured TCP in the design's world/base "
    "frame),\n"
    "trajectory (CSV t, q1..qn, qd1..qdn[, qdd1..qddn], tau1..taun or current1..currentn)";

// The kind of --kind (CLI11 checked the name against kindList) and its --drive option.
const calibration::Kind& parseKind(const std::string& name) {
  const calibration::Kind* kind = calibration::findKind(name);
  ARMSTUDY_CHECK(kind != nullptr, "--kind is checked against the kinds' names");
  return *kind;
}

const calibration::Kind& checkKind(const CommonArgs& a) {
  const calibration::Kind& kind = parseKind(a.kind);
  if (kind.measuresOneDrive() && a.joint.empty())
    throw InputError("", 0, "--drive",
                     "the drive kind needs --drive <joint> (the joint whose drive was measured)");
  if (!kind.measuresOneDrive() && !a.joint.empty())
    throw InputError("", 0, "--drive",
                     "--drive belongs to --kind drive; the " + a.kind + " kind uses every joint");
  return kind;
}

// The kinds' names for CLI11's check of --kind.
std::vector<std::string> kindList() {
  std::vector<std::string> names;
  for (const calibration::Kind* k : calibration::kinds()) names.push_back(k->name());
  return names;
}

void addCommon(CLI::App* cmd, CommonArgs& a) {
  cmd->add_option("design", a.design,
                  "Design file (TOML or URDF); drive kind: with a [[drive]] for the joint")
      ->required();
  addDesignSourceOptions(cmd, a.src);
  cmd->add_option("--kind", a.kind, kKindHelp)->check(CLI::IsMember(kindList()));
  cmd->add_option("--drive", a.joint, "drive kind: joint whose drive was measured, e.g. j6");
  cmd->add_option("--data", a.data, "Measurement CSV in the format of --kind (SI units)")
      ->required();
  cmd->add_option("--out", a.out,
                  "Output folder (default output/calibration/<design>-<joint or kind>)");
  const std::tuple<const char*, int CommonArgs::*, const char*> bin_options[] = {
      {"--speed-bins", &CommonArgs::speed_bins,
       "drive kind, residual map: bins over signed motor speed"},
      {"--load-bins", &CommonArgs::load_bins, "drive kind, residual map: bins over |load torque|"},
      {"--variable-bins", &CommonArgs::variable_bins,
       "tcp/trajectory: bins over each joint variable (q, qd)"},
      {"--workspace-bins", &CommonArgs::workspace_bins,
       "tcp/trajectory: workspace cells per axis (x, y, z)"}};
  for (const auto& [name, bins, help] : bin_options)
    cmd->add_option(name, a.*bins, help)
        ->check(CLI::Range(1, defaults::kMaxResidualBins))
        ->capture_default_str();
}

std::string outDir(const calibration::Kind& kind, const CommonArgs& a, const Model& m) {
  return a.out.empty() ? "output/calibration/" + m.name + "-" +
                             (kind.measuresOneDrive() ? a.joint : std::string(kind.name()))
                       : a.out;
}

// The problem of any kind for the one engine (drive: the measured drive's test-bed data).
std::unique_ptr<calibration::ArmProblem> armProblem(const calibration::Kind& kind,
                                                    const CommonArgs& a, const Model& m) {
  const calibration::ProblemOptions po{a.joint, a.speed_bins, a.load_bins};
  return kind.problem(m, kind.read(a.data, m, po), po);
}

void printArm(const calibration::ArmDiagnosis& d, const calibration::ArmProblem& P) {
  std::printf("%s data of %s vs %s (%d rows, %d channels)\n", d.kind.c_str(), d.design.c_str(),
              P.file.c_str(), P.rows(), P.channels());
  for (const auto& w : d.warnings) std::printf("warning: %s\n", w.c_str());
  std::printf("as designed: RMSE %.4g %s; per channel:\n", d.as_designed.train_rmse,
              P.fit_unit.c_str());
  for (int c = 0; c < P.channels(); ++c) {
    const auto& s = d.as_designed.channel_train[c];
    std::printf("  %-10s RMSE %.4g  bias %+.4g  max %.4g %s\n", P.channel_names[c].c_str(), s.rmse,
                s.bias, s.max_abs, P.channel_units[c].c_str());
  }
  std::printf("noise estimate %.4g %s (lag-1 autocorrelation %.2f); flagged bins: %d of %zu\n",
              d.noise_estimate, P.fit_unit.c_str(), d.noise_rho, d.as_designed_map.flagged(),
              d.as_designed_map.bins.size());
  std::printf(
      "residuals are weighted per channel by the channel's noise estimate; as designed %.3g x the "
      "noise "
      "(RMS over all channels of residual / noise)\n",
      d.as_designed.train_score);
}

// Held-out RMSE per channel in its own unit and in units of its noise, plus the overall figure.
void printChannels(const calibration::ArmDiagnosis& d, const calibration::ArmProblem& P) {
  std::printf("final model, held-out RMSE per channel (noise estimate; ratio):\n");
  for (int c = 0; c < P.channels() && c < static_cast<int>(d.final_fit.channel_heldout.size());
       ++c) {
    const double r = d.final_fit.channel_heldout[c].rmse, s = d.channel_noise[c];
    std::printf("  %-10s %.4g %s (noise %.4g; %.2f x)\n", P.channel_names[c].c_str(), r,
                P.channel_units[c].c_str(), s, s > 0 ? r / s : 0.0);
  }
  std::printf("  overall: %.3g x the noise (dimensionless, held-out)\n", d.final_fit.heldout_score);
}

int fitArm(const calibration::Kind& kind, const CommonArgs& a, const Model& m,
           const std::string& add, bool autoAdd, int folds, unsigned long long seed,
           const std::string& designOut) {
  calibration::ArmFitOptions o;
  o.variable_bins = a.variable_bins;
  o.workspace_bins = a.workspace_bins;
  o.folds = folds;
  o.seed = seed;
  o.auto_add = autoAdd;
  const auto P = armProblem(kind, a, m);
  for (const auto& e : splitList(add)) o.add.push_back(e);
  if (const std::string err = o.validate(); !err.empty()) throw InputError("", 0, "options", err);
  const auto d = calibration::diagnoseArm(*P, o);
  const std::string out = outDir(kind, a, m);
  const calibration::ArmFitFiles files = calibration::writeArmFit(d, *P, m, out, designOut);
  const std::vector<std::string>& notes = files.notes;
  const std::string& path = files.calibrated_design_path;
  printArm(d, *P);
  std::printf("\nmodels (RMSE [%s]; held-out = %d-fold cross-validation, linearised refit):\n",
              P->fit_unit.c_str(), o.folds);
  for (const auto& f : d.ladder)
    std::printf("  %-40s params %2d  train %.4g  held-out %.4g  by region %.4g  AIC %.1f\n",
                f.label.c_str(), f.n_params, f.train_rmse, f.heldout_rmse, f.region_heldout_rmse,
                f.aic);
  std::printf("\ncandidates (best first; first 12 and any with warnings):\n");
  std::printf("  %-26s %-15s %12s %11s %8s  %s\n", "effect", "status", "held-out", "improvement",
              "t", "significant");
  int shown = 0;
  for (const auto& c : d.ranking) {
    const bool show = shown < 12 || !c.warnings.empty();
    if (!show) continue;
    ++shown;
    if (c.status == "ok")
      std::printf("  %-26s %-15s %12.4g %10.1f%% %8.1f  %s\n", c.name.c_str(), c.status.c_str(),
                  c.fit.heldout_rmse, 100 * c.improvement, c.t_statistic,
                  c.significant ? "yes" : "no");
    else
      std::printf("  %-26s %-15s\n", c.name.c_str(), c.status.c_str());
    for (std::size_t k = 0; k < c.warnings.size() && k < 3; ++k)
      std::printf("      warning: %s\n", c.warnings[k].c_str());
    if (c.warnings.size() > 3)
      std::printf("      (%zu more warnings in result.json)\n", c.warnings.size() - 3);
  }
  std::printf("\nverdict: %s\n", d.verdict.c_str());
  std::printf("bins still flagged after the fit: %d of %zu (as designed: %d)\n",
              d.final_map.flagged(), d.final_map.bins.size(), d.as_designed_map.flagged());
  if (d.unexplained_found) {
    std::printf("residual patterns no catalogue effect explains (strongest first):\n");
    for (std::size_t k = 0; k < d.patterns.size() && k < 5 && d.patterns[k].significant; ++k)
      std::printf("  %s: %s (%.0f %% of its residual)\n", d.patterns[k].channel.c_str(),
                  d.patterns[k].description.c_str(), 100 * d.patterns[k].explained);
  }
  printChannels(d, *P);
  if (!d.identifiable.empty()) std::printf("not identifiable: %s\n", d.identifiable.c_str());
  if (!d.added.empty() && d.identifiable.empty()) {
    std::printf("added (in this order):");
    for (const auto& e : d.added) std::printf(" %s", e.c_str());
    std::printf("\nheld-out RMSE before %.4g -> after %.4g %s (x%.2f lower); noise estimate %.4g\n",
                d.rmse_before, d.rmse_after, P->fit_unit.c_str(), d.rmse_before / d.rmse_after,
                d.noise_estimate);
  }
  std::printf("final parameters:\n");
  for (const auto& p : d.final_fit.params)
    std::printf("  %-36s %12.5g %-10s 95%% CI [%.4g, %.4g]%s\n", p.key.c_str(), p.value,
                p.unit.c_str(), p.ci_low, p.ci_high, p.at_bound ? "  (at bound)" : "");
  for (const auto& n : notes) std::printf("note: %s\n", n.c_str());
  std::printf("calibrated design: %s\n", path.empty() ? "none" : path.c_str());
  if (!files.calibrated_urdf_path.empty())
    std::printf("calibrated URDF: %s\n", files.calibrated_urdf_path.c_str());
  std::printf("results in %s/\n", out.c_str());
  return 0;
}

}  // namespace

void addCompareCommand(CLI::App* cmd, Action& action) {
  auto a = std::make_shared<CommonArgs>();
  addCommon(cmd, *a);
  setAction(cmd, action, [a] {
    const calibration::Kind& kind = checkKind(*a);
    const Model m = loadAnyDesign(a->design, a->src.urdf());
    const auto P = armProblem(kind, *a, m);
    calibration::ArmFitOptions o;
    o.variable_bins = a->variable_bins;
    o.workspace_bins = a->workspace_bins;
    const auto d = calibration::compareArm(*P, o);
    calibration::ArmReportOptions ro{outDir(kind, *a, m), "compare"};
    // The compare of a calibrated copy (its check run) titles its figures for that design.
    if (std::filesystem::is_regular_file(a->design))
      ro.shown = calibration::shownDesign(readFileOrThrow(a->design));
    calibration::writeArmReport(d, *P, ro, "");
    printArm(d, *P);
    std::printf("results in %s/ (result.json, plots/, history.csv, error_ladder.svg%s)\n",
                ro.out_dir.c_str(), P->workspace.empty() ? "" : ", *.vti/*.vtp");
    return 0;
  });
}

namespace {

// The candidate effects of each kind (fit --help); the drive effects from their declarations.
std::string effectsByKind() {
  std::string drive_effects;
  for (const drive::EffectDeclaration& d : drive::effectDeclarations())
    drive_effects += std::string(" ") + d.name;
  return "Effects by kind:\n  drive:" + drive_effects +
         "\n  tcp: joint_offset.<joint> link_length.<joint>.<x|y|z> base_offset "
         "joint_compliance.<joint>\n"
         "  trajectory: payload rotor_inertia gravity_tilt link_mass.<joint> <joint>.<drive "
         "effect>";
}

}  // namespace

void addFitCommand(CLI::App* cmd, Action& action) {
  auto a = std::make_shared<CommonArgs>();
  addCommon(cmd, *a);
  cmd->footer(effectsByKind());
  auto add = std::make_shared<std::string>();
  auto autoAdd = std::make_shared<bool>(false);
  auto folds = std::make_shared<int>(defaults::kCvFolds);
  auto seed = std::make_shared<unsigned long long>(defaults::kCvSeed);
  auto designOut = std::make_shared<std::string>();
  cmd->add_option(
      "--add", *add,
      "Effects to add (comma list, in order), e.g. stribeck,asymmetry or joint_offset.j3");
  cmd->add_flag("--auto", *autoAdd, "Add the best significant effect until none is left");
  cmd->add_option("--folds", *folds, "k of k-fold cross-validation (2 to the number of data rows)")
      ->check(CLI::Range(2, 1000000))
      ->capture_default_str();
  cmd->add_option("--seed", *seed, "Seed of the fold assignment")->capture_default_str();
  cmd->add_option(
      "--write-design", *designOut,
      "Path of the calibrated design copy (default <out>/<design>_calibrated.toml; a URDF design "
      "also gets the calibrated URDF beside it, .urdf)");
  setAction(cmd, action, [a, add, autoAdd, folds, seed, designOut] {
    const calibration::Kind& kind = checkKind(*a);
    const Model m = loadAnyDesign(a->design, a->src.urdf());
    return fitArm(kind, *a, m, *add, *autoAdd, *folds, *seed, *designOut);
  });
}

namespace {

// The sizes synth's options ask for, bounded before anything is allocated (README "Input limits").
void checkSynthSizes(const calibration::Kind& kind, const ArmSynthArgs& a) {
  if (kind.id() == calibration::KindId::tcp &&
      !(a.tcp.rows >= 1 && a.tcp.rows <= defaults::kMaxSynthRows))
    throw InputError("command line", 0, "--rows",
                     "the number of poses lies in 1 to " + std::to_string(defaults::kMaxSynthRows));
  if (kind.id() == calibration::KindId::trajectory)
    checkSampling(a.traj.duration_s, a.traj.rate_Hz);
}

// `run`, with an allocation failure reported as an input error naming the options that set the
// size of the synthesized data.
int sizedBy(const calibration::Kind& kind, const Action& run) {
  try {
    return run();
  } catch (const std::bad_alloc&) {
    throw InputError("command line", 0, kind.synthSizeOptions(),
                     "not enough memory for the data these options ask for");
  }
}

// What synth's options hold, for every kind.
struct SynthArgs {
  std::string kind = "drive", design, joint, out;
  std::vector<std::string> hide;
  std::string speeds, loads, temp = "25:45";
  calibration::SynthOptions drive;
  bool no_temperature = false;
  double noise = std::nan("");
  DesignSourceOptions src;
  ArmSynthArgs arm;
};

int synthTcp(const SynthArgs& a, const Model& m) {
  calibration::TcpSynthOptions so = a.arm.tcp;
  so.seed = a.drive.seed;
  if (!std::isnan(a.noise)) so.noise_m = a.noise;
  so.hidden = a.hide;
  const auto data = calibration::synthesizeTcp(m, so);
  writeFileAtomic(a.out, calibration::tcpDataToCsv(data));
  std::printf("wrote %d TCP poses to %s\n", data.rows(), a.out.c_str());
  return 0;
}

int synthTrajectory(const SynthArgs& a, const Model& m) {
  calibration::TrajectorySynthOptions so = a.arm.traj;
  so.seed = a.drive.seed;
  if (!std::isnan(a.noise)) so.noise = a.noise;
  so.hidden = a.hide;
  so.write_qdd = !a.arm.no_qdd;
  const auto data = calibration::synthesizeTrajectory(m, so);
  writeFileAtomic(a.out, calibration::trajectoryDataToCsv(data, so.write_qdd));
  std::printf("wrote %d trajectory samples to %s\n", data.rows(), a.out.c_str());
  return 0;
}

// --hide name[:key=value,...] of the drive kind.
std::pair<drive::Effect, std::vector<std::pair<std::string, double>>> hiddenDriveEffect(
    const std::string& h) {
  const auto colon = h.find(':');
  const drive::Effect e = parseEffectOption(h.substr(0, colon), "--hide");
  std::vector<std::pair<std::string, double>> kv;
  if (colon != std::string::npos)
    for (const auto& item : splitList(h.substr(colon + 1))) {
      const auto eq = item.find('=');
      if (eq == std::string::npos)
        throw InputError("", 0, "--hide", "expected key=value in '" + item + "'");
      kv.emplace_back(item.substr(0, eq), parseNumber(item.substr(eq + 1), "--hide"));
    }
  return {e, kv};
}

int synthDrive(const SynthArgs& a, const Model& m) {
  calibration::SynthOptions so = a.drive;
  if (!std::isnan(a.noise)) so.noise_A = a.noise;
  for (const auto& s : splitList(a.speeds)) so.speeds_radps.push_back(parseNumber(s, "--speeds"));
  for (const auto& s : splitList(a.loads)) so.loads.push_back(parseNumber(s, "--loads"));
  const auto t = splitList(a.temp, ':');
  if (t.size() != 2) throw InputError("", 0, "--temperature", "expected start:end in deg C");
  so.temperature_start_C = parseNumber(t[0], "--temperature");
  so.temperature_end_C = parseNumber(t[1], "--temperature");
  so.write_temperature = !a.no_temperature;
  for (const auto& h : a.hide) so.hidden.push_back(hiddenDriveEffect(h));
  const auto data = calibration::synthesizeDrive(m, a.joint, so);
  writeFileAtomic(a.out, calibration::driveDataToCsv(data));
  std::printf("wrote %d rows to %s\n", data.rows(), a.out.c_str());
  return 0;
}

int synthesize(const SynthArgs& a) {
  const calibration::Kind& kind = parseKind(a.kind);
  return sizedBy(kind, [&a, &kind] {
    if (kind.measuresOneDrive() && a.joint.empty())
      throw InputError("", 0, "--drive", "the drive kind needs --drive <joint>");
    checkOutputPath(a.out);
    checkSynthSizes(kind, a.arm);
    const Model m = loadAnyDesign(a.design, a.src.urdf());
    switch (kind.id()) {
      case calibration::KindId::tcp:
        return synthTcp(a, m);
      case calibration::KindId::trajectory:
        return synthTrajectory(a, m);
      case calibration::KindId::drive:
        break;
    }
    return synthDrive(a, m);
  });
}

void addSynthOptions(CLI::App* cmd, SynthArgs& a) {
  cmd->add_option("design", a.design, "Design file (TOML or URDF)")->required();
  addDesignSourceOptions(cmd, a.src);
  cmd->add_option("--kind", a.kind, kKindHelp)->check(CLI::IsMember(kindList()));
  cmd->add_option("--drive", a.joint, "drive kind: joint whose drive is simulated");
  cmd->add_option("--rows", a.arm.tcp.rows, "tcp: number of poses");
  cmd->add_option("--noise-angle", a.arm.tcp.noise_rad,
                  "tcp: angle noise [rad] (with --orientation)");
  cmd->add_flag("--orientation", a.arm.tcp.orientation, "tcp: also write alpha, beta, gamma");
  cmd->add_option("--duration", a.arm.traj.duration_s, "trajectory: duration [s]");
  cmd->add_option("--rate", a.arm.traj.rate_Hz, "trajectory: sample rate [Hz]");
  cmd->add_flag("--currents", a.arm.traj.currents,
                "trajectory: write motor currents instead of joint efforts");
  cmd->add_flag("--no-qdd", a.arm.no_qdd,
                "trajectory: omit the qdd columns (the reader differentiates qd)");
  cmd->add_option("--still", a.arm.traj.still_joints, "trajectory: joint held still (repeatable)");
  cmd->add_option("--out", a.out, "CSV file to write")->required();
  cmd->add_option(
      "--hide", a.hide,
      "Hidden effect, repeatable: name[:key=value,...], e.g. "
      "stribeck:stribeck_torque=0.03,stribeck_velocity=60,\n"
      "joint_offset.j3:offset=0.01, payload:mass=0.4 (see fit --help for the names per kind)");
  cmd->add_option("--noise", a.noise,
                  "Noise standard deviation: drive [A] (default 0.01), tcp [m] (1e-4), trajectory "
                  "[N m per revolute joint, N per prismatic one, or A] (0.05)");
  cmd->add_option("--noise-correlation", a.drive.noise_rho,
                  "AR(1) correlation of successive noise samples");
  cmd->add_option("--seed", a.drive.seed, "Random seed");
  cmd->add_option("--series", a.drive.series,
                  "Number of test series (each visits the speeds in a new order)");
  cmd->add_option("--speeds", a.speeds,
                  "Motor speed levels [rad/s], comma list (both directions are run)");
  cmd->add_option("--loads", a.loads, "Load torque levels [N m], comma list");
  cmd->add_option("--temperature", a.temp, "Housing temperature start:end [deg C]");
  cmd->add_flag("--no-temperature", a.no_temperature, "Write no temperature column");
}

}  // namespace

void addSynthCommand(CLI::App* cmd, Action& action) {
  auto a = std::make_shared<SynthArgs>();
  addSynthOptions(cmd, *a);
  setAction(cmd, action, [a] { return synthesize(*a); });
}

}  // namespace armstudy::cli
