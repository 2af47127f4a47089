#include "stages/reach/reach_config.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/pose_list_io.hpp"
#include "io/toml_reader.hpp"
#include "study/stage_designs.hpp"
#include "study/tool_axis_check.hpp"

namespace armstudy {

using io::TableReader;

std::string ReachConfig::validate() const {
  const std::string why = ik.validate();
  if (!why.empty()) return why;
  for (const TaskGrid& g : grids) {
    const std::string w = g.validate();
    if (!w.empty()) return "grid '" + g.name + "': " + w;
  }
  return "";
}

namespace {

const char* kAxisNames[3] = {"x", "y", "z"};
const char* kAngleNames[3] = {"alpha", "beta", "gamma"};

TaskSpace readTaskSpace(TableReader& r, const std::string& key, const TaskSpace& fallback) {
  if (!r.has(key)) return fallback;
  TaskSpace ts;
  std::string err;
  if (!parseTaskSpace(r.string(key), ts, err)) r.fail(key, err);
  return ts;
}

// A range table {from, to, step}; `dim` gives the unit checking.
AxisRange readRange(const toml::table& t, const std::string& file, const std::string& key_path,
                    Dimension dim) {
  TableReader r(t, file, key_path);
  AxisRange a;
  a.from = r.quantity("from", dim);
  a.to = r.quantity("to", dim);
  a.step = r.quantity("step", dim);
  r.finish();
  const std::string why = a.validate();
  if (!why.empty()) throw InputError(file, r.line(), key_path, why);
  return a;
}

// x, y, z: a single value or a {from, to, step} range.
AxisRange readAxis(TableReader& r, const std::string& key) {
  const toml::node* n = r.node(key);
  if (!n) r.fail(key, "missing axis (a value such as \"1.2 m\" or {from, to, step})");
  if (const toml::table* t = n->as_table())
    return readRange(*t, r.file(), r.keyPath(key), Dimension::Length);
  AxisRange a;
  a.from = a.to = io::nodeQuantity(*n, Dimension::Length, r.file(), r.keyPath(key));
  a.step = 1;
  return a;
}

// alpha, beta, gamma: a value, an array of values, or a {from, to, step} range.
std::vector<double> readAngles(TableReader& r, const std::string& key) {
  std::vector<double> v;
  const toml::node* n = r.node(key);
  if (!n) return {0.0};
  if (const toml::table* t = n->as_table()) {
    const AxisRange a = readRange(*t, r.file(), r.keyPath(key), Dimension::Angle);
    for (int i = 0; i < a.count(); ++i) v.push_back(a.value(i));
  } else if (const toml::array* arr = n->as_array()) {
    if (arr->empty()) r.fail(key, "empty list of angles");
    for (const auto& e : *arr)
      v.push_back(io::nodeQuantity(e, Dimension::Angle, r.file(), r.keyPath(key)));
  } else {
    v.push_back(io::nodeQuantity(*n, Dimension::Angle, r.file(), r.keyPath(key)));
  }
  return v;
}

void checkName(TableReader& r, const std::string& name, std::set<std::string>& names) {
  if (name.empty()) r.fail("name", "name is empty");
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'))
      r.fail("name", "names use letters, digits, '_' and '-' only (they name output files)");
  if (!names.insert(name).second) r.fail("name", "name '" + name + "' is used twice in [reach]");
}

// The solver's tolerances, starts and seed.
void readIkSettings(TableReader& r, ReachConfig& cfg) {
  cfg.ik.position_tolerance_m =
      r.quantity("position_tolerance", Dimension::Length, cfg.ik.position_tolerance_m);
  if (!(cfg.ik.position_tolerance_m > 0))
    r.fail("position_tolerance", "tolerance must be positive");
  cfg.ik.orientation_tolerance_rad =
      r.quantity("orientation_tolerance", Dimension::Angle, cfg.ik.orientation_tolerance_rad);
  if (!(cfg.ik.orientation_tolerance_rad > 0))
    r.fail("orientation_tolerance", "tolerance must be positive");
  const long long starts = r.integer("starts", cfg.ik.max_starts);
  if (starts < 1 || starts > 10000) r.fail("starts", "starts must be between 1 and 10000");
  cfg.ik.max_starts = static_cast<int>(starts);
  const long long cls = r.integer("classify_starts", cfg.ik.classify_starts);
  if (cls < 0 || cls > 10000)
    r.fail("classify_starts", "classify_starts must be between 0 and 10000");
  cfg.ik.classify_starts = static_cast<int>(cls);
  const long long seed = r.integer("seed", static_cast<long long>(cfg.ik.seed));
  if (seed < 0) r.fail("seed", "seed must not be negative");
  cfg.ik.seed = static_cast<std::uint64_t>(seed);
  cfg.ik.classify_failures = r.boolean("classify", true);
}

// Self-collision and obstacles.
void readCollisionSettings(TableReader& r, const std::vector<const Model*>& evaluated,
                           const std::vector<collision::Obstacle>& obstacles, ReachConfig& cfg) {
  // Designs without collision volumes are evaluated without collisions
  // (ReachConfig::collisionFor).
  bool any_has_model = false;
  for (const Model* m : evaluated) any_has_model |= !m->collision.empty();
  cfg.collision.self = r.boolean("self_collision", any_has_model);
  if (cfg.collision.self && !any_has_model)
    r.fail("self_collision",
           "self_collision = true needs a collision model, but no design of the study has one "
           "(add [[collision]] volumes or set self_collision = false)");
  const bool use_obstacles = r.boolean("obstacles", !obstacles.empty());
  if (use_obstacles && obstacles.empty())
    r.fail("obstacles", "obstacles = true but the study declares no [[obstacle]] entries");
  if (use_obstacles && !any_has_model)
    r.fail("obstacles",
           "obstacles are checked against the designs' collision volumes, but no design of the "
           "study has any (add [[collision]] volumes or set obstacles = false)");
  if (use_obstacles) cfg.collision.obstacles = obstacles;
  cfg.collision.nullspace_escape = r.boolean("nullspace_escape", true);
}

// [reach.search], [reach.audit] and the outputs.
void readSearchAuditOutputs(TableReader& r, const TableReader& top, ReachConfig& cfg) {
  if (const toml::table* t = r.table("search")) {  // docs/reachability.md, "What a status claims"
    TableReader se(*t, top.file(), r.keyPath("search"));
    cfg.search.propagation_rounds =
        se.integerIn("propagation_rounds", cfg.search.propagation_rounds, 0, 1000000);
    cfg.search.collision_starts =
        se.integerIn("collision_starts", cfg.search.collision_starts, 0, 100000);
    cfg.search.best_manipulability =
        se.boolean("best_manipulability", cfg.search.best_manipulability);
    cfg.search.seed = se.seed("seed", cfg.search.seed);
    const std::string order = se.string("order", "ascending");
    if (order != "ascending" && order != "descending")
      se.fail("order",
              "expected \"ascending\" or \"descending\" (the direction grid lines are swept in)");
    cfg.ik.sweep_descending = order == "descending";
    se.finish();
  }
  if (const toml::table* t = r.table("audit")) {  // docs/reachability.md, "The audit"
    TableReader au(*t, top.file(), r.keyPath("audit"));
    cfg.audit_poses = au.integerIn("poses", 100, 0, 10000000);
    cfg.audit_starts = au.integerIn("starts", cfg.audit_starts, 1, 100000);
    cfg.audit_seed = au.seed("seed", cfg.audit_seed);
    au.finish();
  }
  if (r.has("outputs")) {
    cfg.outputs = ReachOutputs{false, false, false};
    for (const std::string& o : r.stringArray("outputs")) {
      if (o == "vtk")
        cfg.outputs.vtk = true;
      else if (o == "images")
        cfg.outputs.images = true;
      else if (o == "surface")
        cfg.outputs.surface = true;
      else
        r.fail("outputs", "unknown output '" + o + "' (expected vtk, images, surface)");
    }
  }
}

// [[reach.grid]] tables.
void readGrids(TableReader& r, const TableReader& top, const TaskSpace& default_space,
               std::set<std::string>& names, ReachConfig& cfg) {
  r.forEachTable("grid", [&](TableReader& g) {
    TaskGrid grid;
    grid.name = g.string("name");
    checkName(g, grid.name, names);
    grid.task_space = readTaskSpace(g, "task_space", default_space);
    for (int a = 0; a < 3; ++a) grid.axes[a] = readAxis(g, kAxisNames[a]);
    std::vector<double> ang[3];
    for (int k = 0; k < 3; ++k) {
      if (g.has(kAngleNames[k]) && !grid.task_space.selected[3 + k])
        g.fail(kAngleNames[k], std::string(kAngleNames[k]) + " is not part of the task space " +
                                   grid.task_space.toString() + " (it is left free); remove it");
      ang[k] = readAngles(g, kAngleNames[k]);
    }
    for (double a : ang[0])
      for (double b : ang[1])
        for (double c : ang[2]) grid.orientations.push_back({a, b, c});
    grid.reference = g.string("reference", "");
    g.finish();
    const std::string why = grid.validate();
    if (!why.empty()) throw InputError(top.file(), g.line(), g.path(), why);
    cfg.grids.push_back(grid);
  });
}

// [[reach.poses]] tables: pose lists read from CSV files.
void readPoseLists(TableReader& r, const std::string& study_dir, const TaskSpace& default_space,
                   std::set<std::string>& names, ReachConfig& cfg,
                   std::vector<std::pair<std::string, std::string>>& files_read) {
  namespace fs = std::filesystem;
  r.forEachTable("poses", [&](TableReader& p) {
    const std::string name = p.string("name");
    checkName(p, name, names);
    const TaskSpace ts = readTaskSpace(p, "task_space", default_space);
    const std::string file = p.string("file");
    const fs::path resolved =
        fs::path(file).is_absolute() ? fs::path(file) : fs::path(study_dir) / file;
    if (!fs::exists(resolved))
      p.fail("file",
             "pose list '" + file + "' does not exist (looked for " + resolved.string() + ")");
    p.finish();
    const std::string path = resolved.lexically_normal().string();
    const std::string text = readFileOrThrow(path);
    PoseList list = parsePoseCsv(text, path, ts);
    list.name = name;
    files_read.emplace_back(path, contentHash(text));
    cfg.pose_lists.push_back(std::move(list));
  });
}

}  // namespace

void readReachSection(TableReader& top, const std::string& study_dir,
                      const std::vector<const Model*>& models,
                      const std::vector<collision::Obstacle>& obstacles, ReachConfig& cfg,
                      std::vector<std::pair<std::string, std::string>>& files_read) {
  const toml::table* t = top.table("reach");
  if (!t) return;
  cfg.enabled = true;
  TableReader r(*t, top.file(), "reach");
  const StageDesigns stage_designs = readStageDesigns(r, top.file(), models);
  cfg.designs = stage_designs.names;
  cfg.tool_axes = stage_designs.tool_axes;
  const std::vector<const Model*> evaluated = stage_designs.evaluated(models);
  const TaskSpace default_space = readTaskSpace(r, "task_space", TaskSpace::spraying());
  readIkSettings(r, cfg);
  readCollisionSettings(r, evaluated, obstacles, cfg);
  readSearchAuditOutputs(r, top, cfg);
  std::set<std::string> names;
  readGrids(r, top, default_space, names, cfg);
  readPoseLists(r, study_dir, default_space, names, cfg, files_read);
  bool points_axis = false;  // the spraying-type tasks: position, the tool axis, the roll free
  auto axisTask = [](const TaskSpace& t) {
    return t.selected[3] && !t.selected[4] && t.selected[5];
  };
  for (const auto& g : cfg.grids) points_axis = points_axis || axisTask(g.task_space);
  for (const auto& p : cfg.pose_lists) points_axis = points_axis || axisTask(p.task_space);
  if (points_axis) requireToolAxes(stage_designs, evaluated, top.file(), r.line(), "reach");
  r.finish();
  if (cfg.grids.empty() && cfg.pose_lists.empty())
    throw InputError(top.file(), r.line(), "reach",
                     "[reach] needs at least one [[reach.grid]] or [[reach.poses]]");
}

}  // namespace armstudy
