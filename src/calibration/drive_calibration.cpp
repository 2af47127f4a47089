#include "calibration/drive_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "common/angles.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "common/format.hpp"
#include "common/rng.hpp"
#include "drive/drive_chain.hpp"
#include "io/csv_io.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::calibration {

using drive::Effect;
using drive::EffectParameter;
using drive::FrictionParams;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
int idx(Effect e) { return static_cast<int>(e); }

// One catalogue instance: the refit of the design's terms, or one effect the design lacks.
struct DriveTag {
  bool refit = false;
  Effect effect = Effect::Coulomb;  // the added effect (refit: unused)
  std::vector<std::string> keys;    // [drive.friction] key of each fitted parameter
};

class DriveProblem : public ArmProblem {
 public:
  DriveProblem(const Model& model, const std::string& joint, const DriveData& data, int speed_bins,
               int load_bins)
      : joint_(joint),
        drive_(requireDrive(model, joint)),
        design_(drive::frictionParams(model, drive_)),
        data_(data) {
    setSource("drive", model.name, data);
    channel_names = {"current"};
    channel_units = {"A"};
    fit_unit = "A";
    weight = Eigen::VectorXd::Ones(1);
    setMeasurements(data);
    setOperatingVariables(data, speed_bins, load_bins);
    addEffects(joint, data);
    warnNarrowTemperature(data);
  }

  FrictionParams friction(const EffectValues& values) const {
    FrictionParams p = design_;
    for (const auto& v : values) {
      const DriveTag& t = tags_[v.effect];
      const ArmEffect& info = catalogue[v.effect];
      if (!t.refit) p.on[idx(t.effect)] = true;
      for (std::size_t j = 0; j < t.keys.size(); ++j)
        *drive::parameter(p, t.keys[j]) = info.params[j].design + v.x[j];
      if (info.hasProfile()) *drive::parameter(p, info.profile.key) = v.profile;
    }
    return p;
  }

  // The Model carries every drive parameter: no notes.
  Model calibratedModel(const Model& model, const EffectValues& values,
                        std::vector<std::string>&) const override {
    const FrictionParams p = friction(values);
    Model cal = model;
    Drive* d = nullptr;
    for (Drive& x : cal.drives)
      if (x.joint == joint_) d = &x;
    ARMSTUDY_CHECK(d != nullptr, "the problem's drive is in its design");
    if (d->friction_law.empty()) d->friction_law = "none";
    const std::vector<Effect> law = drive::lawEffects(p.law);
    for (Effect e : drive::kAllEffects) {
      if (!p.has(e)) continue;
      for (const std::string& key : drive::effectKeys(e))
        d->friction[key] = drive::parameter(p, key);
      if (drive::isTemperatureEffect(e))
        d->friction["reference_temperature"] = p.reference_temperature_C;
      const std::string entry = joint_ + "." + drive::toString(e);
      if (std::find(law.begin(), law.end(), e) == law.end() &&
          std::find(cal.effects.begin(), cal.effects.end(), entry) == cal.effects.end())
        cal.effects.push_back(entry);
    }
    return cal;
  }

  Eigen::MatrixXd predict(const EffectValues& values) const override {
    const FrictionParams p = friction(values);
    Eigen::MatrixXd out(data_.rows(), 1);
    for (int i = 0; i < data_.rows(); ++i)
      out(i, 0) = drive::testBedCurrent(drive_, p, data_.speed[i], data_.load[i], theta_[i]);
    return out;
  }

 private:
  std::string joint_;
  Drive drive_;
  FrictionParams design_;
  std::vector<DriveTag> tags_;

  // The measured currents and the temperature each sample is evaluated at.
  void setMeasurements(const DriveData& data) {
    const int n = data.rows();
    measured.resize(n, 1);
    for (int i = 0; i < n; ++i) measured(i, 0) = data.current[i];
    theta_.resize(n);
    for (int i = 0; i < n; ++i)
      theta_[i] = data.hasTemperature() ? data.temperature[i] : design_.reference_temperature_C;
    bool temperature_term = false;
    for (const drive::EffectDeclaration& d : drive::effectDeclarations())
      temperature_term = temperature_term || (d.needs_temperature && design_.has(d.effect));
    if (temperature_term && !data.hasTemperature())
      warnings.push_back(
          "the design has a temperature term but the data has no temperature column; "
          "evaluated at the reference temperature");
  }

  // Operating variables, the speed x |load| grid map, the held-out regions (quadrants) and the
  // Stribeck velocities the profile is scanned at.
  void setOperatingVariables(const DriveData& data, int speed_bins, int load_bins) {
    const int n = data.rows();
    const bool joint_side = design_.joint_side;
    const double side =
        joint_side ? 1.0 / drive_.gear_ratio : 1.0;  // motor speed -> law-side speed
    BinVariable speed{"speed", "rad/s", data.speed, false},
        load{"load", joint_side ? "N" : "N m", data.load, false};
    variables = {speed, load};
    if (data.hasTemperature())
      variables.push_back({"temperature", "deg C", data.temperature, false});
    BinVariable abs_load{"|load|", load.unit, {}, false};
    for (double l : data.load) abs_load.values.push_back(std::abs(l));
    grid = {speed, abs_load};
    grid_bins = {speed_bins, load_bins};
    bin_variables = false;
    auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    std::vector<double> av;
    for (double v : data.speed) av.push_back(std::abs(v));
    if (n > 0) {
      const double mv = median(av), ml = median(abs_load.values);
      for (int i = 0; i < n; ++i)
        regions.push_back((av[i] > mv ? 2 : 0) + (abs_load.values[i] > ml ? 1 : 0));
      region_count = 4;
    }
    // The Stribeck velocity is identifiable only inside the measured speed range (law side).
    double vmin = kInf, vmax = 0;
    for (double v : av) {
      vmin = std::min(vmin, v * side);
      vmax = std::max(vmax, v * side);
    }
    if (n > 0 && vmax > 0) {
      const int G = defaults::kStribeckGridPoints;
      const double a = std::log(0.5 * vmin), b = std::log(vmax);
      for (int g = 0; g < G; ++g) speed_grid_.push_back(std::exp(a + (b - a) * g / (G - 1)));
    }
  }

  std::string unitOf(const EffectParameter& ep) const {
    return design_.joint_side ? ep.unit_joint : ep.unit_motor;
  }
  // Declared typical values are motor side; joint-side laws see them scaled (typical values only).
  double typicalOf(const EffectParameter& ep) const {
    return design_.joint_side ? ep.typical * drive::jointSideScale(ep, drive_.gear_ratio)
                              : ep.typical;
  }
  ArmParam param(const EffectParameter& ep, double design_value) const {
    ArmParam p;
    p.key = ep.key;
    p.unit = unitOf(ep);
    p.lower = ep.lower - design_value;
    p.upper = ep.upper - design_value;
    p.typical = typicalOf(ep);
    p.step = std::max(std::abs(p.typical), 1e-12);  // the prediction is linear in every parameter
    p.design = design_value;
    return p;
  }
  // A profiled parameter (the Stribeck velocity) on the log grid of measured law-side speeds.
  void profile(ArmEffect& e, const EffectParameter& ev) const {
    e.profile = {ev.key, unitOf(ev), 0, kInf, typicalOf(ev), 0, 0};
    e.profile_grid = speed_grid_;
  }
  // The effect's parameters: fitted ones start at `start(parameter)`, a profiled one is scanned.
  template <class Start>
  void addParams(ArmEffect& e, DriveTag& t, const drive::EffectDeclaration& d, Start start) const {
    for (const EffectParameter& ep : d.params) {
      if (ep.profiled) {
        profile(e, ep);
        continue;
      }
      e.params.push_back(param(ep, start(ep)));
      t.keys.push_back(ep.key);
    }
  }

  // The candidate effects: the refit of the design's own terms, then every term it lacks.
  void addEffects(const std::string& joint, const DriveData& data) {
    // The refit of the design's own terms (thesis Table 4.5: eq. 3.30 refitted to the test bed).
    {
      ArmEffect e;
      e.name = e.effect = kRefitEffect;
      e.joint = joint;
      e.pattern = "the design's own friction terms with other values";
      DriveTag t;
      t.refit = true;
      std::string terms;
      for (const drive::EffectDeclaration& d : drive::effectDeclarations()) {
        if (!design_.has(d.effect)) continue;
        terms += (terms.empty() ? "" : "+") + std::string(d.name);
        addParams(e, t, d, [&](const EffectParameter& ep) { return design_.*ep.field; });
      }
      e.pattern += " (" + terms + ")";
      if (!e.params.empty()) {
        add(e, t);
        added_first.push_back(kRefitEffect);  // every fit refits them first, then ranks
      }
    }
    for (const drive::EffectDeclaration& d : drive::effectDeclarations()) {
      if (design_.has(d.effect)) continue;
      if (d.needs_temperature && !data.hasTemperature()) continue;  // needs a temperature column
      ArmEffect e;
      e.name = e.effect = d.name;
      e.joint = joint;
      e.pattern = d.pattern;
      DriveTag t{false, d.effect, {}};
      // From zero: a Stribeck torque starts at the design's Coulomb level (no change at zero).
      addParams(e, t, d, [&](const EffectParameter&) {
        return d.starts_at_coulomb ? design_.coulomb : 0.0;
      });
      add(e, t);
    }
  }

  void warnNarrowTemperature(const DriveData& data) {
    if (data.hasTemperature()) {
      const auto [tmin, tmax] =
          std::minmax_element(data.temperature.begin(), data.temperature.end());
      const double span = *tmax - *tmin;
      if (span > 0 && span < defaults::kMinTemperatureSpan_K)
        warnings.push_back("temperature varies by only " + formatG(span, 3) +
                           " K in the data: the temperature effects are weakly identifiable");
    }
  }

  void add(const ArmEffect& e, DriveTag t) {
    catalogue.push_back(e);
    tags_.push_back(std::move(t));
  }
  DriveData data_;
  std::vector<double> theta_;
  std::vector<double> speed_grid_;  // law-side speeds, rad/s
};

}  // namespace

std::unique_ptr<ArmProblem> makeDriveProblem(const Model& model, const std::string& joint,
                                             const DriveData& data, int speed_bins, int load_bins) {
  return std::make_unique<DriveProblem>(model, joint, data, speed_bins, load_bins);
}

const Drive& requireDrive(const Model& model, const std::string& joint) {
  std::string names;
  for (const Drive& d : model.drives) {
    if (d.joint == joint) return d;
    names += names.empty() ? "" : ", ";
    names += d.joint;
  }
  throw InputError(model.file, 0, "drive",
                   "design '" + model.name + "' has no [[drive]] for joint '" + joint + "'" +
                       (names.empty() ? " (it has no drives)" : " (drives: " + names + ")"));
}

DriveData readDriveData(const std::string& path) {
  const io::CsvTable t = io::readCsv(path, {{"speed", "load_torque", "current"}, {"temperature"}});
  DriveData d;
  d.file = path;
  d.hash = fileHash(path);
  d.speed = t.column("speed");
  d.load = t.column("load_torque");
  d.current = t.column("current");
  if (t.has("temperature")) d.temperature = t.column("temperature");
  d.lines = t.row_lines;
  d.warnings = t.extraColumnWarnings();
  for (int i = 0; i < d.rows(); ++i)
    if (d.speed[i] == 0)
      throw InputError(
          path, d.lines[i], "speed",
          "standstill row (speed 0): the friction laws do not predict static friction; "
          "remove the row");
  return d;
}

namespace {

void setParam(FrictionParams& p, const std::string& key, double v) {
  double* x = drive::parameter(p, key);
  if (!x) throw InputError("", 0, key, "unknown friction parameter '" + key + "'");
  *x = v;
}

}  // namespace

DriveData synthesizeDrive(const Model& model, const std::string& joint, const SynthOptions& o) {
  const Drive& d = requireDrive(model, joint);
  FrictionParams truth = drive::frictionParams(model, d);
  for (const auto& [e, overrides] : o.hidden) {
    const drive::EffectDeclaration& info = drive::declaration(e);
    if (!truth.has(e))
      for (const auto& ep : info.params) setParam(truth, ep.key, ep.typical);
    truth.on[idx(e)] = true;
    for (const auto& [k, v] : overrides) {
      bool belongs = k == "reference_temperature" && info.needs_temperature;
      for (const auto& ep : info.params) belongs = belongs || ep.key == k;
      if (!belongs)
        throw InputError("", 0, k,
                         "parameter '" + k + "' does not belong to the effect '" + info.name + "'");
      setParam(truth, k, v);
    }
  }
  for (const drive::EffectDeclaration& d : drive::effectDeclarations())
    for (const EffectParameter& ep : d.params)
      if (ep.positive && truth.has(d.effect) && !(truth.*ep.field > ep.lower))
        throw InputError("", 0, ep.key, drive::inWords(ep.key) + " must be positive");
  std::vector<double> speeds = o.speeds_radps;
  if (speeds.empty())
    for (double rpm : {100, 250, 500, 1000, 1500, 2000, 2500, 3000, 3500})
      speeds.push_back(rpm * std::numbers::pi / 30.0);
  std::vector<double> loads = o.loads;
  if (loads.empty()) loads = {1.3, 4.0, 6.5, 9.0, 11.7, 14.5, 17.0};
  std::vector<double> levels;
  for (double s : speeds) {
    if (!(s > 0))
      throw InputError("", 0, "speeds", "speed levels must be positive (both directions are run)");
    levels.push_back(s);
    levels.push_back(-s);
  }
  for (double l : loads)
    if (!(l >= 0)) throw InputError("", 0, "loads", "load levels must not be negative");
  if (o.series < 1) throw InputError("", 0, "series", "at least one test series");
  if (double(o.series) * double(levels.size() * loads.size()) > defaults::kMaxSynthRows)
    throw InputError("", 0, "series",
                     "series x speed levels x load levels exceeds " +
                         std::to_string(defaults::kMaxSynthRows) + " rows");
  if (!(o.noise_A >= 0) || !(o.noise_rho >= 0 && o.noise_rho < 1))
    throw InputError("", 0, "noise", "noise must be >= 0 and its correlation in [0, 1)");
  rng::SplitMix64 rng{o.seed};
  DriveData out;
  out.file = "synthetic";
  const int total = o.series * static_cast<int>(levels.size() * loads.size());
  double e_prev = 0;
  int row = 0;
  for (int s = 0; s < o.series; ++s) {
    std::vector<double> order = levels;
    for (int i = static_cast<int>(order.size()) - 1; i > 0; --i)
      std::swap(order[i], order[rng.next() % static_cast<std::uint64_t>(i + 1)]);
    for (double v : order)
      for (double l : loads) {
        // Warm-up: the housing temperature approaches its end value over the run.
        const double t = total > 1 ? double(row) / (total - 1) : 0.0;
        const double theta = o.temperature_end_C -
                             (o.temperature_end_C - o.temperature_start_C) * std::exp(-3.0 * t);
        const double load = v > 0 ? l : -l;  // the load opposes the motion
        const double e = o.noise_rho * e_prev +
                         std::sqrt(1 - o.noise_rho * o.noise_rho) * o.noise_A * rng.normal();
        e_prev = e;
        out.speed.push_back(v);
        out.load.push_back(load);
        out.current.push_back(drive::testBedCurrent(d, truth, v, load, theta) + e);
        if (o.write_temperature) out.temperature.push_back(theta);
        out.lines.push_back(row + 2);
        ++row;
      }
  }
  return out;
}

std::string driveDataToCsv(const DriveData& d) {
  std::vector<std::string> h = {"speed", "load_torque", "current"};
  std::vector<std::vector<double>> cols = {d.speed, d.load, d.current};
  if (d.hasTemperature()) {
    h.push_back("temperature");
    cols.push_back(d.temperature);
  }
  return io::formatCsv(h, cols);
}

}  // namespace armstudy::calibration
