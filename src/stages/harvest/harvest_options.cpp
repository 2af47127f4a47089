#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "dynamics/approach_tracking.hpp"
#include "io/approach_io.hpp"
#include "io/files.hpp"
#include "io/toml_reader.hpp"
#include "io/units.hpp"
#include "io/vtk_io.hpp"
#include "report/image.hpp"
#include "report/markdown.hpp"
#include "stages/harvest/harvest_stage.hpp"

namespace armstudy::harvest {

namespace fs = std::filesystem;
using io::TableReader;
using nlohmann::ordered_json;
// ---------------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------------

std::string HarvestOptions::validate() const {
  if (!(rate_Hz > 0) || !std::isfinite(rate_Hz)) return "rate must be positive";
  if (!std::isfinite(temperature_C)) return "temperature must be finite";
  if (!start_offset.allFinite()) return "start offset must be finite";
  if (plot_fruits < 0) return "plot_fruits must be >= 0";
  if (!(w_joint_limits >= 0) || !(w_manipulability >= 0)) return "objective weights must be >= 0";
  std::string err;
  if (!row.validate(err)) return "row: " + err;
  if (!approach.validate(err)) return "approach: " + err;
  if (grid)
    for (const auto& a : grid->axes)
      if (std::string why = a.validate(); !why.empty()) return "grid: " + why;
  return "";
}

namespace {

AxisRange readAxis(TableReader& r, const std::string& key) {
  const toml::node* n = r.node(key);
  if (!n) r.fail(key, "missing axis (a value such as \"1.2 m\" or {from, to, step})");
  AxisRange a;
  if (const toml::table* t = n->as_table()) {
    TableReader tr(*t, r.file(), r.keyPath(key));
    a.from = tr.quantity("from", Dimension::Length);
    a.to = tr.quantity("to", Dimension::Length);
    a.step = tr.quantity("step", Dimension::Length);
    tr.finish();
  } else {
    a.from = a.to = io::nodeQuantity(*n, Dimension::Length, r.file(), r.keyPath(key));
    a.step = 1;
  }
  if (std::string why = a.validate(); !why.empty()) r.fail(key, why);
  return a;
}

}  // namespace

HarvestOptions readHarvestOptions(TableReader& r, const SectionInput& in) {
  std::vector<std::string> designs;
  for (const Model* m : in.designs) designs.push_back(m->name);
  HarvestOptions o;
  if (r.has("designs")) {
    o.designs = r.stringArray("designs");
    if (o.designs.empty()) r.fail("designs", "empty list of designs");
    for (const auto& d : o.designs)
      if (std::find(designs.begin(), designs.end(), d) == designs.end())
        r.fail("designs", "design '" + d + "' is not part of the study");
  }
  o.rate_Hz = r.number("rate", o.rate_Hz);
  if (!(o.rate_Hz > 0) || o.rate_Hz > 1e5) r.fail("rate", "rate must lie in (0, 100000] Hz");
  o.temperature_C = r.number("temperature", o.temperature_C);
  o.tool_beta_rad = r.quantity("tool_beta", Dimension::Angle, o.tool_beta_rad);
  if (r.has("start_offset")) {
    const toml::array* a = r.array("start_offset");
    if (!a || a->size() != 3) r.fail("start_offset", "expected three lengths [dx, dy, dz]");
    for (int i = 0; i < 3; ++i)
      o.start_offset[i] =
          io::nodeQuantity(*a->get(i), Dimension::Length, r.file(), r.keyPath("start_offset"));
  }
  o.plot_fruits = static_cast<int>(r.integer("plot_fruits", o.plot_fruits));
  if (o.plot_fruits < 0) r.fail("plot_fruits", "must be >= 0");

  if (const toml::table* t = r.table("row")) {
    TableReader rr(*t, r.file(), r.keyPath("row"));
    const long long seed = rr.integer("seed", 1);
    if (seed < 0) rr.fail("seed", "seed must be >= 0");
    o.row.seed = static_cast<std::uint64_t>(seed);
    o.row.stems = static_cast<int>(rr.integer("stems", o.row.stems));
    if (o.row.stems < 1 || o.row.stems > 10000) rr.fail("stems", "stems must lie in [1, 10000]");
    o.row.fruits_per_stem = static_cast<int>(rr.integer("fruits_per_stem", o.row.fruits_per_stem));
    if (o.row.fruits_per_stem < 1 || o.row.fruits_per_stem > 100)
      rr.fail("fruits_per_stem", "fruits_per_stem must lie in [1, 100]");
    o.row.first_stem_y_m = rr.quantity("first_stem_y", Dimension::Length, o.row.first_stem_y_m);
    o.row.fruit_z.mean = rr.quantity("fruit_z_mean", Dimension::Length, o.row.fruit_z.mean);
    o.row.fruit_z.sd = rr.quantity("fruit_z_sd", Dimension::Length, o.row.fruit_z.sd);
    o.row.fruit_z.min = rr.quantity("fruit_z_min", Dimension::Length, o.row.fruit_z.min);
    o.row.fruit_z.max = rr.quantity("fruit_z_max", Dimension::Length, o.row.fruit_z.max);
    o.row.fruit_angle_min_rad =
        rr.quantity("fruit_angle_min", Dimension::Angle, o.row.fruit_angle_min_rad);
    o.row.fruit_angle_max_rad =
        rr.quantity("fruit_angle_max", Dimension::Angle, o.row.fruit_angle_max_rad);
    std::string err;
    if (!o.row.validate(err)) throw InputError(r.file(), rr.line(), r.keyPath("row"), err);
    rr.finish();
  }
  {
    const toml::table* t = r.table("approach");
    if (!t) r.fail("approach", "missing table [harvest.approach] (duration is required)");
    TableReader ar(*t, r.file(), r.keyPath("approach"));
    o.approach = readApproachOptions(ar);
    ar.finish();
  }
  // Samples per approach (rate x duration): at least one Euler step (a rate so low that 1 / rate
  // overflows passes "> 0"), at most defaults::kMaxTrajectorySamples (held in memory).
  if (!(o.approach.duration_s * o.rate_Hz >= 1))
    r.fail("rate", "rate x approach duration must give at least one step (rate >= 1 / duration)");
  if (o.approach.duration_s * o.rate_Hz > defaults::kMaxTrajectorySamples)
    r.fail("rate", "rate x approach duration exceeds 1e6 samples per approach");
  if (const toml::table* t = r.table("objective")) {
    TableReader orr(*t, r.file(), r.keyPath("objective"));
    o.w_joint_limits = orr.number("joint_limits", o.w_joint_limits);
    o.w_manipulability = orr.number("manipulability", o.w_manipulability);
    if (const std::string bad = implausibleWeight(o.w_joint_limits, true); !bad.empty())
      orr.fail("joint_limits", bad);
    if (const std::string bad = implausibleWeight(o.w_manipulability, true); !bad.empty())
      orr.fail("manipulability", bad);
    orr.finish();
  }
  if (const toml::table* t = r.table("grid")) {
    TableReader gr(*t, r.file(), r.keyPath("grid"));
    HarvestGrid g;
    g.axes[0] = readAxis(gr, "x");
    g.axes[1] = readAxis(gr, "y");
    g.axes[2] = readAxis(gr, "z");
    g.gamma_rad = gr.quantity("gamma", Dimension::Angle, 0.0);
    const long pts = static_cast<long>(g.axes[0].count()) * g.axes[1].count() * g.axes[2].count();
    if (pts > 1000000) gr.fail("x", "grid has more than 1e6 points");
    gr.finish();
    o.grid = g;
  }
  const std::string why = o.validate();
  ARMSTUDY_CHECK(why.empty(), "harvest reader and validate disagree: " + why);
  return o;
}

}  // namespace armstudy::harvest
