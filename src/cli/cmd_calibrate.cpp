// CLI for model versus measurement of a drive (docs/calibration.md): compare, fit, synth.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "calibration/drive_calibration.hpp"
#include "calibration/drive_report.hpp"
#include "cli/commands.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::cli {
namespace {

using calibration::DriveFitOptions;

std::vector<std::string> splitList(const std::string& s, char sep = ',') {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string x; std::getline(ss, x, sep);)
    if (!x.empty()) out.push_back(x);
  return out;
}

drive::Effect parseEffectOption(const std::string& name, const std::string& option) {
  drive::Effect e;
  if (!drive::parseEffect(name, e))
    throw InputError("", 0, option,
                     "unknown effect '" + name +
                         "' (expected coulomb, viscous, load_coulomb, load_viscous, stribeck, asymmetry, temperature)");
  return e;
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

struct CommonArgs {
  std::string design, joint, data, out;
  int speed_bins = defaults::kSpeedBins, load_bins = defaults::kLoadBins;
};

void addCommon(CLI::App* cmd, CommonArgs& a) {
  cmd->add_option("design", a.design, "Design file (TOML) with a [[drive]] for the joint")->required();
  cmd->add_option("--drive", a.joint, "Joint whose drive was measured, e.g. j6")->required();
  cmd->add_option("--data", a.data, "Test-bed CSV: speed, load_torque, current[, temperature] (SI)")->required();
  cmd->add_option("--out", a.out, "Output folder (default output/calibration/<design>-<joint>)");
  cmd->add_option("--speed-bins", a.speed_bins, "Residual map: bins over signed motor speed");
  cmd->add_option("--load-bins", a.load_bins, "Residual map: bins over |load torque|");
}

std::string outDir(const CommonArgs& a, const Model& m) {
  return a.out.empty() ? "output/calibration/" + m.name + "-" + a.joint : a.out;
}

void printFit(const char* label, const calibration::ModelFit& m) {
  std::printf("  %-44s params %2d  train %.4g A  held-out %.4g A  AIC %.1f\n", label, m.n_params, m.train_rmse,
              m.heldout_rmse, m.aic);
}

void printHeader(const calibration::DriveDiagnosis& d, const calibration::DriveData& data) {
  std::printf("drive %s of %s vs %s (%d rows%s)\n", d.joint.c_str(), d.design.c_str(), data.file.c_str(), data.rows(),
              data.hasTemperature() ? ", with temperature" : "");
  for (const auto& w : d.warnings) std::printf("warning: %s\n", w.c_str());
  const auto& c = d.as_designed_cmp;
  std::printf("as designed: current RMSE %.4g A, bias %+.4g A, max %.4g A  (friction torque RMSE %.4g N m)\n",
              c.current.rmse, c.current.bias, c.current.max_abs, c.friction_torque.rmse);
  std::printf("noise estimate %.4g A (lag-1 autocorrelation %.2f); flagged bins: %d of %zu\n", d.noise_estimate,
              d.noise_rho, c.map.flagged(), c.map.bins.size());
}

}  // namespace

void addCompareCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare a design's drive model with test-bed measurements: RMSE, bias and max per channel,\n"
      "plots of measured vs predicted and residual vs every operating variable, a residual map over\n"
      "speed x load with the bins the noise cannot explain flagged; appends to history.csv.\n"
      "Example: armstudy compare designs/final_prototype_9dof.toml --drive j6 --data studies/data/drive_testbed_module_b2.csv");
  auto a = std::make_shared<CommonArgs>();
  addCommon(cmd, *a);
  cmd->callback([&action, a] {
    action = [a] {
      const Model m = loadDesign(a->design);
      const calibration::DriveData data = calibration::readDriveData(a->data);
      DriveFitOptions o;
      o.speed_bins = a->speed_bins;
      o.load_bins = a->load_bins;
      const auto d = calibration::compareDrive(m, a->joint, data, o);
      calibration::DriveReportOptions ro;
      ro.out_dir = outDir(*a, m);
      ro.command = "compare";
      const auto sum = calibration::writeDriveReport(d, m, data, ro);
      printHeader(d, data);
      std::printf("results in %s/ (result.json, plots/, history.csv, error_ladder.svg)\n", ro.out_dir.c_str());
      (void)sum;
      return 0;
    };
  });
}

void addFitCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "fit",
      "Refit a design's drive friction to test-bed data, rank the candidate effects that could be\n"
      "missing by k-fold cross-validated error (with held-out-by-region scores, confidence intervals\n"
      "and identifiability warnings), optionally add effects, and write a calibrated copy of the design.\n"
      "Example: armstudy fit designs/final_prototype_9dof.toml --drive j6 --data studies/data/drive_testbed_module_b2.csv --auto");
  auto a = std::make_shared<CommonArgs>();
  addCommon(cmd, *a);
  auto add = std::make_shared<std::string>();
  auto autoAdd = std::make_shared<bool>(false);
  auto folds = std::make_shared<int>(defaults::kCvFolds);
  auto seed = std::make_shared<unsigned long long>(defaults::kCvSeed);
  auto designOut = std::make_shared<std::string>();
  cmd->add_option("--add", *add, "Effects to add (comma list, in order), e.g. stribeck,asymmetry");
  cmd->add_flag("--auto", *autoAdd, "Add the best significant effect until none is left");
  cmd->add_option("--folds", *folds, "k of k-fold cross-validation");
  cmd->add_option("--seed", *seed, "Seed of the fold assignment");
  cmd->add_option("--write-design", *designOut, "Path of the calibrated design copy (default <out>/<design>_calibrated.toml)");
  cmd->callback([&action, a, add, autoAdd, folds, seed, designOut] {
    action = [a, add, autoAdd, folds, seed, designOut] {
      const Model m = loadDesign(a->design);
      DriveFitOptions o;
      o.speed_bins = a->speed_bins;
      o.load_bins = a->load_bins;
      o.folds = *folds;
      o.seed = *seed;
      o.auto_add = *autoAdd;
      for (const auto& e : splitList(*add)) o.add.push_back(parseEffectOption(e, "--add"));
      if (const std::string err = o.validate(); !err.empty()) throw InputError("", 0, "options", err);
      calibration::requireDrive(m, a->joint);
      const calibration::DriveData data = calibration::readDriveData(a->data);
      const auto d = calibration::diagnoseDrive(m, a->joint, data, o);
      calibration::DriveReportOptions ro;
      ro.out_dir = outDir(*a, m);
      ro.command = "fit";
      ro.write_calibrated_design = true;
      ro.calibrated_design_path = *designOut;
      const auto sum = calibration::writeDriveReport(d, m, data, ro);
      printHeader(d, data);
      std::printf("\nmodels (current RMSE; held-out = %d-fold cross-validation):\n", o.folds);
      for (const auto& f : d.ladder) printFit(f.label.c_str(), f);
      std::printf("\ncandidates for the refit model (best first):\n");
      std::printf("  %-13s %-15s %12s %11s %8s  %s\n", "effect", "status", "held-out [A]", "improvement", "t", "significant");
      for (const auto& c : d.ranking) {
        if (c.status == "ok")
          std::printf("  %-13s %-15s %12.4g %10.1f%% %8.1f  %s\n", drive::toString(c.effect), c.status.c_str(),
                      c.fit.heldout_rmse, 100 * c.improvement, c.t_statistic, c.significant ? "yes" : "no");
        else
          std::printf("  %-13s %-15s\n", drive::toString(c.effect), c.status.c_str());
        for (const auto& w : c.warnings) std::printf("      warning: %s\n", w.c_str());
      }
      std::printf("\nverdict: %s\n", d.missing_effect_found
                                          ? ("missing effect: " + std::string(drive::toString(d.ranking.front().effect))).c_str()
                                          : "no significant missing effect");
      if (!d.added.empty()) {
        std::printf("added:");
        for (auto e : d.added) std::printf(" %s", drive::toString(e));
        std::printf("\nheld-out RMSE before %.4g A -> after %.4g A (x%.2f lower); noise estimate %.4g A\n",
                    d.rmse_before, d.rmse_after, d.rmse_before / d.rmse_after, d.noise_estimate);
      }
      std::printf("final parameters:\n");
      for (const auto& p : d.final_fit.params)
        std::printf("  %-24s %12.5g %-10s 95%% CI [%.4g, %.4g]%s\n", p.key.c_str(), p.value, p.unit.c_str(), p.ci_low,
                    p.ci_high, p.at_bound ? "  (at bound)" : "");
      std::printf("calibrated design: %s\nresults in %s/\n", sum.calibrated_design_path.c_str(), ro.out_dir.c_str());
      return 0;
    };
  });
}

void addSynthCommand(CLI::App& app, Action& action) {
  auto* cmd = app.add_subcommand(
      "synth",
      "Virtual drive test bed: write test-bed CSV data from a design's drive plus hidden effects and\n"
      "noise (seeded, reproducible). Speeds run in both directions, loads oppose the motion, the\n"
      "housing temperature warms up over the run.\n"
      "Example: armstudy synth designs/final_prototype_9dof.toml --drive j6 --hide stribeck:stribeck_velocity=60 --out bed.csv");
  auto joint = std::make_shared<std::string>();
  auto design = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto hide = std::make_shared<std::vector<std::string>>();
  auto speeds = std::make_shared<std::string>();
  auto loads = std::make_shared<std::string>();
  auto temp = std::make_shared<std::string>("25:45");
  auto o = std::make_shared<calibration::SynthOptions>();
  auto noTemp = std::make_shared<bool>(false);
  cmd->add_option("design", *design, "Design file (TOML)")->required();
  cmd->add_option("--drive", *joint, "Joint whose drive is simulated")->required();
  cmd->add_option("--out", *out, "CSV file to write")->required();
  cmd->add_option("--hide", *hide,
                  "Hidden effect, repeatable: name[:key=value,...], e.g. stribeck:stribeck_torque=0.03,stribeck_velocity=60");
  cmd->add_option("--noise", o->noise_A, "Current noise standard deviation [A]");
  cmd->add_option("--noise-correlation", o->noise_rho, "AR(1) correlation of successive noise samples");
  cmd->add_option("--seed", o->seed, "Random seed");
  cmd->add_option("--series", o->series, "Number of test series (each visits the speeds in a new order)");
  cmd->add_option("--speeds", *speeds, "Motor speed levels [rad/s], comma list (both directions are run)");
  cmd->add_option("--loads", *loads, "Load torque levels [N m], comma list");
  cmd->add_option("--temperature", *temp, "Housing temperature start:end [deg C]");
  cmd->add_flag("--no-temperature", *noTemp, "Write no temperature column");
  cmd->callback([&action, design, joint, out, hide, speeds, loads, temp, o, noTemp] {
    action = [design, joint, out, hide, speeds, loads, temp, o, noTemp] {
      const Model m = loadDesign(*design);
      calibration::SynthOptions so = *o;
      for (const auto& s : splitList(*speeds)) so.speeds_radps.push_back(parseNumber(s, "--speeds"));
      for (const auto& s : splitList(*loads)) so.loads.push_back(parseNumber(s, "--loads"));
      const auto t = splitList(*temp, ':');
      if (t.size() != 2) throw InputError("", 0, "--temperature", "expected start:end in deg C");
      so.temperature_start_C = parseNumber(t[0], "--temperature");
      so.temperature_end_C = parseNumber(t[1], "--temperature");
      so.write_temperature = !*noTemp;
      for (const auto& h : *hide) {
        const auto colon = h.find(':');
        const drive::Effect e = parseEffectOption(h.substr(0, colon), "--hide");
        std::vector<std::pair<std::string, double>> kv;
        if (colon != std::string::npos)
          for (const auto& item : splitList(h.substr(colon + 1))) {
            const auto eq = item.find('=');
            if (eq == std::string::npos) throw InputError("", 0, "--hide", "expected key=value in '" + item + "'");
            kv.emplace_back(item.substr(0, eq), parseNumber(item.substr(eq + 1), "--hide"));
          }
        so.hidden.emplace_back(e, kv);
      }
      const auto data = calibration::synthesizeDrive(m, *joint, so);
      writeFileAtomic(*out, calibration::driveDataToCsv(data));
      std::printf("wrote %d rows to %s\n", data.rows(), out->c_str());
      return 0;
    };
  });
}

}  // namespace armstudy::cli
