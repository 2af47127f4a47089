#include "engine/study_file.hpp"

#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "common/names.hpp"
#include "engine/registry.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/ssv_io.hpp"
#include "io/toml_reader.hpp"
#include "io/urdf_arm.hpp"
#include "io/urdf_io.hpp"
#include "io/variant.hpp"
#include "model/model_notes.hpp"

namespace armstudy {

using io::TableReader;

namespace {

struct Override {
  std::string key;
  std::vector<double> values;  // one value for `set`, several for `sweep`
  int line;
};

std::vector<Override> readOverrides(TableReader& r, const std::string& section, const Model& base,
                                    bool sweep) {
  std::vector<Override> out;
  const toml::table* t = r.table(section);
  if (!t) return out;
  for (auto&& [k, v] : *t) {
    Override o;
    o.key = std::string(k.str());
    o.line = static_cast<int>(v.source().begin.line);
    const std::string key_path = r.keyPath(section) + "." + o.key;
    Dimension dim;
    std::string err;
    if (!modelEntryDimension(base, o.key, dim, err))
      throw InputError(r.file(), o.line, key_path, err);
    if (sweep) {
      if (!v.is_array() || v.as_array()->empty())
        throw InputError(r.file(), o.line, key_path, "a sweep needs a non-empty array of values");
      for (const auto& e : *v.as_array())
        o.values.push_back(io::nodeQuantity(e, dim, r.file(), key_path));
    } else {
      o.values.push_back(io::nodeQuantity(v, dim, r.file(), key_path));
    }
    out.push_back(o);
  }
  return out;
}

// [[obstacle]] entries (docs/collision.md): name, type (sphere/point, capsule/line, triangle),
// points in the task frame W, radius.
std::vector<collision::Obstacle> readObstacles(TableReader& top) {
  std::vector<collision::Obstacle> out;
  top.forEachTable("obstacle", [&](TableReader& r) {
    collision::Obstacle o;
    o.name = r.name("name", "obstacle", "_-",
                    "obstacle names use letters, digits, '_' and '-' only (they appear in pair "
                    "names and fields)");
    for (const auto& other : out)
      if (other.name == o.name) r.fail("name", "obstacle '" + o.name + "' is defined twice");
    const io::SsvGeometry g = io::readSsvGeometry(r, true, "the task frame W");
    o.type = g.type;
    o.p_W = g.p;
    o.radius_m = g.radius_m;
    r.finish();
    if (static_cast<int>(out.size()) == collision::kMaxObstacles)
      r.fail("name", "more than " + std::to_string(collision::kMaxObstacles) +
                         " obstacles are not supported");
    out.push_back(std::move(o));
  });
  return out;
}

namespace fs = std::filesystem;

// [study]: the study's name, description, question and assumptions.
void readStudyHeader(TableReader& top, Study& s) {
  TableReader r = top.requiredTable("study");
  s.name =
      r.name("name", "study", "_-",
             "study names use letters, digits, '_' and '-' only (they name the output folder)");
  s.description = r.string("description", "");
  s.question = r.string("question", "");
  s.assumptions = r.stringArray("assumptions");
  r.finish();
}

// A [[design]]'s URDF options: base and tip links, package folders relative to the study.
UrdfOptions readUrdfOptions(TableReader& r, const std::string& path, const fs::path& dir) {
  UrdfOptions uo;  // URDF designs (docs/study-format.md): chain and package folders
  uo.base_link = r.string("base_link", "");
  uo.tip_link = r.string("tip_link", "");
  if (const toml::table* pk = r.table("packages")) {
    TableReader pr(*pk, path, r.path() + ".packages");
    for (auto&& [k, v] : *pk) {
      const std::string dir_text = pr.string(std::string(k.str()));
      const fs::path d = fs::path(dir_text).is_absolute() ? fs::path(dir_text) : dir / dir_text;
      if (!fs::is_directory(d))
        pr.fail(std::string(k.str()), "package folder '" + dir_text +
                                          "' does not exist (looked for " +
                                          d.lexically_normal().string() + ")");
      uo.packages.emplace_back(std::string(k.str()), d.lexically_normal().string());
    }
    pr.finish();
  }
  return uo;
}

// A URDF design's base placement, TCP offset and name from its [[design]] entry.
void readUrdfPlacement(TableReader& r, const std::string& path, Model& m) {
  // a URDF has no task-frame placement, TCP offset or design name of ours
  auto pose = [&](const char* key, PoseXYZABG& p) {
    const toml::table* t = r.table(key);
    if (!t) return;
    TableReader pr(*t, path, r.path() + "." + key);
    p.x = pr.quantity("x", Dimension::Length, 0.0);
    p.y = pr.quantity("y", Dimension::Length, 0.0);
    p.z = pr.quantity("z", Dimension::Length, 0.0);
    p.alpha = pr.quantity("alpha", Dimension::Angle, 0.0);
    p.beta = pr.quantity("beta", Dimension::Angle, 0.0);
    p.gamma = pr.quantity("gamma", Dimension::Angle, 0.0);
    pr.finish();
  };
  pose("base", m.base);
  PoseXYZABG offset;  // the TCP offset is given in the tip link frame: T_NT = T_N,tip * offset
  pose("tcp", offset);
  const Eigen::Isometry3d T_NT = m.tcp.toIsometry() * offset.toIsometry();
  const Eigen::Vector3d abg = T_NT.linear().eulerAngles(0, 1, 2);  // R = Rx Ry Rz
  m.tcp = {T_NT.translation().x(),
           T_NT.translation().y(),
           T_NT.translation().z(),
           abg[0],
           abg[1],
           abg[2]};
  m.name = r.string("name", m.name);
  if (!isPlainName(m.name, kDesignNamePunctuation))
    r.fail("name",
           "design names use letters, digits, '_', '-' and '.' only, not dots alone (they name "
           "files)");
  m.finalize();
}

// The design file of a [[design]] entry. A URDF's input error names the study's line too: the
// entry's tip_link or base_link when the URDF error is about them, else its file key.
Model loadDesignOfEntry(TableReader& r, const std::string& file, const UrdfOptions& uo, bool urdf) {
  try {
    return loadAnyDesign(file, uo);
  } catch (const InputError& e) {
    if (!urdf) throw;
    const std::string key = (e.key() == "tip_link" || e.key() == "base_link") && r.has(e.key())
                                ? e.key()
                                : std::string("file");
    const std::string where =
        e.file() + (e.line() > 0 ? ":" + std::to_string(e.line()) : "") + ": key '" + e.key() + "'";
    r.fail(key, "in the URDF design " + where + ": " + e.message());
  }
}

// One [[design]] entry: its file (relative to the study), loaded, with the entry's settings.
Model readDesign(TableReader& r, const std::string& path, const fs::path& dir,
                 double& reference_reach_m) {
  const std::string file = r.string("file");
  const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : dir / file;
  std::error_code ec;  // a name too long for the file system reads as not there
  if (!fs::exists(resolved, ec))
    r.fail("file",
           "design file '" + file + "' does not exist (looked for " + resolved.string() + ")");
  const UrdfOptions uo = readUrdfOptions(r, path, dir);
  const bool urdf = isUrdfPath(resolved.string());
  if (!urdf)
    for (const char* k : {"base_link", "tip_link", "packages", "base", "tcp", "name"})
      if (r.has(k))
        r.fail(k, "base_link, tip_link, packages, base, tcp and name belong to URDF design files");
  Model m = loadDesignOfEntry(r, resolved.lexically_normal().string(), uo, urdf);
  if (urdf) {
    readUrdfPlacement(r, path, m);
    applyToolAxisFromArm(m);  // the entry's TCP decides whether it lies on the last joint's axis
  }
  if (r.has("tool_axis")) {  // any design: override its file's axis
    m.tool_axis_T = readToolAxis(r, "tool_axis", m.tool_axis_T);
    notes::toolAxisNamed(m, "tool_axis of the study's [[design]] entry");
  }
  reference_reach_m = r.quantity("reference_reach_m", Dimension::Length, 0.0);
  if (r.has("reference_reach_m") && !(reference_reach_m > 0))
    r.fail("reference_reach_m", "a reference reach must be above 0 (m, or a string with its unit)");
  r.finish();
  return m;
}

// The designs of a study: bases owns them, by_name points into bases.
struct BaseDesigns {
  std::vector<Model> bases;
  std::map<std::string, const Model*> by_name;
};

// Every [[design]] entry, in order, into s.designs and s.inputs; names must be unique.
void readDesigns(TableReader& top, const std::string& path, const fs::path& dir, Study& s,
                 BaseDesigns& d) {
  d.bases.reserve(64);
  const toml::array* designs = top.array("design");
  if (!designs || designs->empty())
    throw InputError(path, 1, "design", "a study needs at least one [[design]] entry");
  top.forEachTable("design", [&](TableReader& r) {
    double reference_reach_m = 0;
    Model m = readDesign(r, path, dir, reference_reach_m);
    if (d.by_name.count(m.name))
      r.fail("file", "design name '" + m.name + "' appears twice in this study");
    s.inputs.push_back({m.file, m.file_hash});
    d.bases.push_back(std::move(m));
    d.by_name[d.bases.back().name] = &d.bases.back();
    s.designs.push_back({d.bases.back(), d.bases.back().name, {}, reference_reach_m});
  });
}

// The variants of one [[variant]] entry: the Cartesian product of its sweeps, each with its sets.
void addVariantProduct(TableReader& r, const std::string& path, const Model& base,
                       const std::vector<Override>& sets, const std::vector<Override>& sweeps,
                       VariantGeometry geometry, Study& s) {
  // Cartesian product of the sweeps; keys in sorted order (TOML tables are unordered), the
  // first key varies slowest, so variant names and order are stable.
  std::vector<std::size_t> counter(sweeps.size(), 0);
  for (bool done = false; !done;) {
    std::vector<std::pair<std::string, double>> ov;
    for (const auto& o : sets) ov.emplace_back(o.key, o.values[0]);
    for (std::size_t k = 0; k < sweeps.size(); ++k)
      ov.emplace_back(sweeps[k].key, sweeps[k].values[counter[k]]);
    // Overrides, the geometry that follows (collision volumes, inertias), validation.
    Model m = deriveVariant(base, ov, path, r.line(), geometry);
    for (const auto& d : s.designs)
      if (d.model.name == m.name)
        throw InputError(path, r.line(), r.path(), "variant '" + m.name + "' is defined twice");
    s.designs.push_back({m, base.name, ov, 0.0});
    // Advance the odometer; the last sweep key varies fastest.
    int k = static_cast<int>(sweeps.size()) - 1;
    for (; k >= 0; --k) {
      if (++counter[k] < sweeps[k].values.size()) break;
      counter[k] = 0;
    }
    done = k < 0;
  }
}

// Every [[variant]] entry: of which design, its sets and sweeps, its geometry; into s.designs.
void readVariants(TableReader& top, const std::string& path, const BaseDesigns& d, Study& s) {
  top.forEachTable("variant", [&](TableReader& r) {
    const std::string of = r.string("of");
    auto it = d.by_name.find(of);
    if (it == d.by_name.end())
      r.fail("of", "variant of unknown design '" + of + "' (list it in a [[design]] entry first)");
    const Model& base = *it->second;
    std::vector<Override> sets = readOverrides(r, "set", base, false);
    std::vector<Override> sweeps = readOverrides(r, "sweep", base, true);
    // Collision volumes and inertias follow moved link ends unless the variant is the same arm.
    const std::string geometry_text = r.string("geometry", "follows");
    if (geometry_text != "follows" && geometry_text != "fixed")
      r.fail("geometry",
             "geometry is \"follows\" (volumes and inertias adapt to the new link lengths) or "
             "\"fixed\" (kept from the base design)");
    const VariantGeometry geometry =
        geometry_text == "fixed" ? VariantGeometry::Fixed : VariantGeometry::Follows;
    r.finish();
    if (sets.empty() && sweeps.empty())
      throw InputError(path, r.line(), r.path(), "a variant needs `set` or `sweep` entries");
    addVariantProduct(r, path, base, sets, sweeps, geometry, s);
  });
}

// [regression]: where the baseline lives and how far each metric may move.
RegressionSpec readRegression(TableReader& top, const std::string& path, const fs::path& dir) {
  RegressionSpec spec;
  spec.baseline_path = (dir / (fs::path(path).stem().string() + ".baseline.json")).string();
  const toml::table* t = top.table("regression");
  if (!t) return spec;
  TableReader r(*t, path, "regression");
  if (r.has("baseline"))
    spec.baseline_path = (dir / r.string("baseline")).lexically_normal().string();
  r.forEachTable("tolerance", [&](TableReader& tr) {
    ToleranceRule rule;
    rule.line = tr.line();
    rule.metric = tr.string("metric");
    if (rule.metric.empty()) tr.fail("metric", "empty metric pattern");
    rule.abs = tr.number("abs", 0.0);
    rule.rel = tr.number("rel", 0.0);
    rule.flips = static_cast<int>(tr.integer("flips", 0));
    if (rule.abs < 0) tr.fail("abs", "tolerance must not be negative");
    if (rule.rel < 0) tr.fail("rel", "tolerance must not be negative");
    if (rule.flips < 0) tr.fail("flips", "allowed flips must not be negative");
    spec.rules.push_back(rule);
  });
  r.finish();
  return spec;
}

// Every stage reads its own section(s); the registry says which stages exist, in run order.
void readStageSections(TableReader& top, const fs::path& dir, Study& s) {
  const std::vector<const Model*> models = s.models();
  const std::string study_dir = dir.string();
  SectionInput in{top, study_dir, models, s.obstacles, s.inputs};
  for (const Stage* stage : stageRegistry())
    if (auto settings = stage->read(in)) s.sections.push_back({stage, std::move(settings)});
}

}  // namespace

// Reads the study file: header, designs, variants, obstacles, regression, stage sections.
Study loadStudy(const std::string& path) {
  return loadStudyText(readFileOrThrow(path), path, fs::path(path).parent_path().string());
}

Study loadStudyText(const std::string& text, const std::string& path, const std::string& folder) {
  Study s;
  s.file = path;
  s.file_hash = contentHash(text);
  s.inputs.push_back({path, s.file_hash});
  const toml::table root = io::parseTomlText(text, path);
  TableReader top(root, path, "");
  readStudyHeader(top, s);
  const fs::path dir = folder;
  BaseDesigns bases;
  readDesigns(top, path, dir, s, bases);
  readVariants(top, path, bases, s);
  s.obstacles = readObstacles(top);
  s.regression = readRegression(top, path, dir);
  readStageSections(top, dir, s);
  top.finish();
  return s;
}

}  // namespace armstudy
