#include "stages/dexterity/dexterity_io.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "io/toml_reader.hpp"
#include "io/units.hpp"
#include "study/tool_axis_check.hpp"

namespace armstudy::dexterity {

namespace {

// { min = ..., max = ..., step = ... } or { min, max, count } or a single value { value = ... }.
AxisRange readRange(io::TableReader& parent, const std::string& key, Dimension dim) {
  const toml::table* t = parent.table(key);
  if (!t) parent.fail(key, "expected a table such as { min = ..., max = ..., step = ... }");
  io::TableReader r(*t, parent.file(), parent.keyPath(key));
  AxisRange a;
  if (r.has("value")) {
    a.min = a.max = r.quantity("value", dim);
    a.count = 1;
    r.finish();
    return a;
  }
  a.min = r.quantity("min", dim);
  a.max = r.quantity("max", dim);
  if (r.has("step") == r.has("count")) r.fail("step", "give exactly one of `step` and `count`");
  if (!(a.max > a.min))
    r.fail("max", "max must be greater than min (or use `value` for a single sample)");
  if (r.has("step")) {
    const double step = r.quantity("step", dim);
    if (!(step > 0)) r.fail("step", "step must be > 0");
    const double n = (a.max - a.min) / step;
    const double rounded = std::round(n);
    if (std::abs(n - rounded) > 1e-6 * std::max(1.0, n))
      r.fail("step", "the range max - min is not a whole multiple of step");
    if (rounded + 1 > 1e7) r.fail("step", "too many samples");
    a.count = static_cast<int>(rounded) + 1;
  } else {
    const long long c = r.integer("count", 0);
    if (c < 2 || c > 10000000) r.fail("count", "count must be between 2 and 1e7 when min < max");
    a.count = static_cast<int>(c);
  }
  r.finish();
  return a;
}

double nonNegative(io::TableReader& r, const std::string& key, double fallback, Dimension dim) {
  if (!r.has(key)) return fallback;
  const double v = r.quantity(key, dim);  // rejects NaN/Inf
  if (v < 0) r.fail(key, "must be >= 0");
  return v;
}

// An objective weight: 0 (the term off) or plausible (io/units.hpp implausibleWeight).
double weight(io::TableReader& r, const std::string& key, double fallback) {
  if (!r.has(key)) return fallback;
  const double v = r.quantity(key, Dimension::Dimensionless);
  if (const std::string bad = implausibleWeight(v, true); !bad.empty()) r.fail(key, bad);
  return v;
}

double positive(io::TableReader& r, const std::string& key, double fallback, Dimension dim) {
  if (!r.has(key)) return fallback;
  const double v = r.quantity(key, dim);
  if (!(v > 0)) r.fail(key, "must be > 0");
  return v;
}

// The collision keys (docs/dexterity.md, "Collisions"): self_collision (default: on when a design
// has a collision model), obstacles (the study's [[obstacle]]s, default: on when it declares any),
// clearance, and [dexterity.row], the stems of the row around the map's stem.
void readCollision(io::TableReader& r, const SectionInput& in, DexterityOptions& o) {
  bool any_has_model = false;
  for (const Model* m : o.designs.evaluated(in.designs)) any_has_model |= !m->collision.empty();
  StemCollision& c = o.collision;
  c.self = r.boolean("self_collision", any_has_model);
  if (c.self && !any_has_model)
    r.fail("self_collision",
           "self_collision = true needs a collision model, but no design of the study has one "
           "(add [[collision]] volumes or set self_collision = false)");
  const bool use_obstacles = r.boolean("obstacles", !in.obstacles.empty());
  if (use_obstacles && in.obstacles.empty())
    r.fail("obstacles", "obstacles = true but the study declares no [[obstacle]] entries");
  if (use_obstacles) c.obstacles = in.obstacles;
  c.clearance_m = nonNegative(r, "clearance", 0.0, Dimension::Length);
  if (const toml::table* t = r.table("row")) {
    io::TableReader rw(*t, r.file(), r.keyPath("row"));
    StemRow row;
    row.stem = rw.boolean("stem", true);
    row.neighbours = rw.integerIn("neighbours", 1, 0, 100);
    if (row.neighbours > 0) row.spacing_m = positive(rw, "spacing", 0.0, Dimension::Length);
    if (row.neighbours > 0 && !rw.has("spacing"))
      rw.fail("neighbours", "neighbouring stems need `spacing` (thesis Table 2.2: \"192 mm\")");
    row.radius_m = positive(rw, "stem_radius", row.radius_m, Dimension::Length);
    row.bottom_m = rw.quantity("bottom", Dimension::Length, row.bottom_m);
    row.top_m = rw.quantity("top", Dimension::Length, row.top_m);
    const std::string why = row.validate();
    if (!why.empty()) rw.fail(row.neighbours > 0 ? "spacing" : "stem_radius", why);
    std::vector<double> sweep;
    if (const toml::array* a = rw.array("spacing_sweep")) {
      for (const toml::node& n : *a) {
        const double v =
            io::nodeQuantity(n, Dimension::Length, rw.file(), rw.keyPath("spacing_sweep"));
        StemRow other = row;
        other.spacing_m = v;
        other.neighbours = v > 0 ? std::max(row.neighbours, 1) : 0;
        if (!(v >= 0) || !other.validate().empty())
          rw.fail("spacing_sweep",
                  "every spacing must be 0 (no neighbouring stems) or larger "
                  "than the stem diameter");
        sweep.push_back(v);
      }
    }
    rw.finish();
    const std::vector<collision::Obstacle> study = c.obstacles;
    auto withRow = [&](const StemRow& r) {
      StemCollision rc = c;
      rc.obstacles = rowObstacles(o.grid, r);
      rc.obstacles.insert(rc.obstacles.end(), study.begin(), study.end());
      return rc;
    };
    c = withRow(row);
    o.row_spacing_m = row.neighbours > 0 ? row.spacing_m : 0.0;
    for (const double v : sweep) {
      StemRow other = row;
      other.spacing_m = v;
      other.neighbours = v > 0 ? std::max(row.neighbours, 1) : 0;
      o.row_sweep.push_back(withRow(other));
      o.row_sweep_spacing_m.push_back(v);
    }
  }
  if (!c.obstacles.empty() && !any_has_model)
    r.fail(r.has("row") ? "row" : "obstacles",
           "obstacles are checked against the designs' collision volumes, but no design of the "
           "study has any (add [[collision]] volumes or remove them)");
  if (c.obstacles.size() > static_cast<std::size_t>(defaults::kMaxObstacles))
    r.fail("row", "more than " + std::to_string(defaults::kMaxObstacles) +
                      " obstacles (stems and [[obstacle]]s)");
}

}  // namespace

DexterityOptions readDexterityOptions(io::TableReader& r, const SectionInput& in) {
  DexterityOptions o;
  o.designs = readStageDesigns(r, r.file(), in.designs);
  const std::vector<const Model*> designs = o.designs.evaluated(in.designs);
  StemGrid& g = o.grid;
  g.stem_x_m = r.quantity("stem_x", Dimension::Length);
  g.stem_y_m = r.quantity("stem_y", Dimension::Length);
  g.radius_m = r.quantity("radius", Dimension::Length);
  if (!(g.radius_m > 0)) r.fail("radius", "stem radius must be > 0");
  g.gamma_rad = readRange(r, "gamma", Dimension::Angle);
  if (g.gamma_rad.max - g.gamma_rad.min > 2 * std::numbers::pi + 1e-9)
    r.fail("gamma", "gamma range exceeds a full turn");
  g.z_m = readRange(r, "z", Dimension::Length);
  const std::string task = r.string("task", "position_axis");
  if (task == "position_axis")
    g.task = PoseTaskKind::PositionAxis;
  else if (task == "full")
    g.task = PoseTaskKind::FullPose;
  else
    r.fail("task",
           "expected \"position_axis\" (tool axis towards the stem, roll free) or \"full\"");
  if (g.task == PoseTaskKind::PositionAxis)
    requireToolAxes(o.designs, designs, r.file(), r.line(), r.path());
  g.roll_rad = r.quantity("roll", Dimension::Angle, 0.0);
  if (r.has("roll") && g.task != PoseTaskKind::FullPose)
    r.fail("roll", "roll is only used with task = \"full\"");
  const std::string space = r.string("measure_space", "translational");
  if (!metrics::parseMeasureSpace(space, o.measure_space))
    r.fail("measure_space", "expected \"translational\" or \"full\"");
  o.ellipsoids = r.boolean("ellipsoids", true);
  readCollision(r, in, o);
  if (r.has("direction")) {
    const std::vector<double> d = r.numberArray("direction");
    if (d.size() != 3) r.fail("direction", "direction u needs three components [x, y, z]");
    o.fixed_direction = true;
    o.direction_W = Eigen::Vector3d(d[0], d[1], d[2]);
    const double nrm = o.direction_W.norm();
    if (!std::isfinite(nrm) || nrm == 0) r.fail("direction", "direction u has zero length");
    if (std::abs(nrm - 1.0) > 1e-6)
      r.fail("direction", "direction u must be a unit vector (length " + std::to_string(nrm) + ")");
  }
  if (const toml::table* t = r.table("objective")) {
    io::TableReader ob(*t, r.file(), r.keyPath("objective"));
    o.w_joint_limits = weight(ob, "joint_limits", o.w_joint_limits);
    o.w_manipulability = weight(ob, "manipulability", o.w_manipulability);
    o.w_transmission = weight(ob, "transmission", o.w_transmission);
    o.w_collision = weight(ob, "collision", o.w_collision);
    o.collision_safety_distance_m =
        positive(ob, "collision_safety_distance", o.collision_safety_distance_m, Dimension::Length);
    if (o.w_collision > 0 && !o.collision.enabled())
      ob.fail("collision", "the collision term needs self_collision or obstacles");
    if (ob.has("joint_limit_activation")) {
      o.joint_limit_activation = ob.quantity("joint_limit_activation", Dimension::Dimensionless);
      if (!(o.joint_limit_activation > 0 && o.joint_limit_activation < 0.5))
        ob.fail("joint_limit_activation", "must lie in (0, 0.5) (fraction of the joint range)");
    }
    ob.finish();
  }
  if (const toml::table* t = r.table("solver")) {
    io::TableReader sv(*t, r.file(), r.keyPath("solver"));
    if (sv.has("joint_weights")) {
      o.joint_weights = sv.numberArray("joint_weights");
      for (double w : o.joint_weights)
        if (const std::string bad = implausibleWeight(w, false); !bad.empty())
          sv.fail("joint_weights", "joint weight " + bad);
    }
    o.position_tolerance_m =
        positive(sv, "position_tolerance", o.position_tolerance_m, Dimension::Length);
    o.orientation_tolerance_rad =
        positive(sv, "orientation_tolerance", o.orientation_tolerance_rad, Dimension::Angle);
    o.cold_starts = sv.integerIn("cold_starts", o.cold_starts, 1, 1000);
    o.solve.max_iterations = sv.integerIn("max_iterations", o.solve.max_iterations, 1, 100000);
    o.nullspace.max_iterations =
        sv.integerIn("nullspace_max_iterations", o.nullspace.max_iterations, 0, 100000);
    o.nullspace.relative_improvement = nonNegative(
        sv, "relative_improvement", o.nullspace.relative_improvement, Dimension::Dimensionless);
    o.nullspace.quasi_newton = sv.boolean("quasi_newton", o.nullspace.quasi_newton);
    o.nullspace.damping_lambda0 =
        nonNegative(sv, "damping", o.nullspace.damping_lambda0, Dimension::Dimensionless);
    o.nullspace.damping_m0 =
        nonNegative(sv, "damping_threshold", o.nullspace.damping_m0, Dimension::Dimensionless);
    sv.finish();
  }
  if (const toml::table* t = r.table("search")) {  // docs/dexterity.md, "How a map value is found"
    io::TableReader se(*t, r.file(), r.keyPath("search"));
    o.seed_starts = se.integerIn("seed_starts", o.seed_starts, 0, 10000);
    o.seed_stride = se.integerIn("seed_stride", o.seed_stride, 1, 100000);
    o.propagation_rounds = se.integerIn("propagation_rounds", o.propagation_rounds, 0, 1000000);
    o.collision_starts = se.integerIn("collision_starts", o.collision_starts, 0, 10000);
    o.search_seed = se.seed("seed", o.search_seed);
    const std::string order = se.string("order", "ascending");
    if (order != "ascending" && order != "descending")
      se.fail("order",
              "expected \"ascending\" or \"descending\" (the gamma order of the chained rows)");
    o.descending = order == "descending";
    se.finish();
  }
  if (const toml::table* t = r.table("audit")) {  // docs/dexterity.md, "The audit"
    io::TableReader au(*t, r.file(), r.keyPath("audit"));
    o.audit_cells = au.integerIn("cells", 50, 0, 10000000);
    o.audit_starts = au.integerIn("starts", o.audit_starts, 1, 100000);
    o.audit_seed = au.seed("seed", o.audit_seed);
    au.finish();
  }
  r.finish();
  const std::string v = o.validate();
  if (!v.empty()) throw InputError(r.file(), r.line(), r.path(), v);
  for (const Model* m : designs) {
    const std::string w = o.validateFor(*m);
    if (!w.empty())
      throw InputError(r.file(), r.line(o.joint_weights.empty() ? "task" : "solver"), r.path(), w);
  }
  return o;
}

}  // namespace armstudy::dexterity
