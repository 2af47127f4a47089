#include "engine/run.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>

#include "armstudy/version.hpp"
#include "common/errors.hpp"
#include "io/files.hpp"
#include "report/arm_drawing.hpp"
#include "report/html_report.hpp"
#include "report/view3d.hpp"
#include "study/checkpoint.hpp"
#include "study/scene.hpp"

namespace armstudy {

using nlohmann::ordered_json;

static ordered_json poseJson(const PoseXYZABG& p) {
  return ordered_json{{"x_m", p.x},           {"y_m", p.y},         {"z_m", p.z},
                      {"alpha_rad", p.alpha}, {"beta_rad", p.beta}, {"gamma_rad", p.gamma}};
}

static ordered_json modelJson(const Model& m) {
  ordered_json j;
  j["name"] = m.name;
  j["file"] = m.file;
  j["file_hash"] = m.file_hash;
  j["dof"] = m.dof();
  j["source"] = m.source;
  j["assumptions"] = m.assumptions;
  ordered_json joints = ordered_json::array();
  for (const Joint& jt : m.joints) {
    ordered_json r = {{"name", jt.name}, {"type", toString(jt.type)}};
    r.update(poseJson(jt.offset));
    r["min"] = jt.limits.q_min;
    r["max"] = jt.limits.q_max;
    r["max_velocity"] = jt.limits.qd_max;
    joints.push_back(r);
  }
  j["joints"] = joints;
  j["tcp"] = poseJson(m.tcp);
  j["tool_axis"] = {m.tool_axis_T.x(), m.tool_axis_T.y(), m.tool_axis_T.z()};
  j["base"] = poseJson(m.base);
  return j;
}

std::string modelToJson(const Model& model, int indent) { return modelJson(model).dump(indent); }

std::string studyFingerprint(const Study& study) {
  std::string f = std::string("armstudy=") + kVersion + " " + kGitRevision + "\n";
  for (const auto& in : study.inputs) f += "input:" + in.path + "=" + in.hash + "\n";
  return f;
}

// Removes the files an earlier complete run listed in its manifest (for --overwrite), so results
// of designs no longer in the study do not linger.
static void removePreviousResults(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const fs::path man = dir / "manifest.json";
  if (!fs::exists(man)) return;
  try {
    const auto j = nlohmann::json::parse(readFileOrThrow(man.string()));
    // Only regular files inside the folder: canonical paths (symbolic links resolved), compared by
    // path components, never by string prefix (out/mini_other is not inside out/mini). Entries
    // that name the folder itself ("."), a subfolder or anything else are left alone, so a
    // manifest cannot stop the run.
    const fs::path base = fs::weakly_canonical(dir);
    for (const auto& f : j.value("files", std::vector<std::string>{})) {
      std::error_code ec;
      const fs::path p = fs::weakly_canonical(dir / f, ec);
      const fs::path rel = p.lexically_relative(base);
      if (ec || rel.empty() || rel == "." || *rel.begin() == ".." || rel.is_absolute()) continue;
      if (fs::is_regular_file(fs::symlink_status(p, ec))) fs::remove(p, ec);
    }
  } catch (const nlohmann::json::exception&) {
    // An unreadable manifest lists nothing to remove; new files replace old ones by name.
  }
  fs::remove(man);
}

RunSummary runStudy(const Study& study, const RunOptions& options) {
  return runStudy(study, options, singleProcess());
}

namespace {

// Runs `f` on this rank and agrees with the others: when any rank failed, the lowest failing one
// rethrows its error and the others throw OtherRankFailed.
template <class F>
void agreed(const Ranks& ranks, F&& f) {
  std::exception_ptr err;
  try {
    f();
  } catch (...) {
    err = std::current_exception();
  }
  const int first = ranks.firstFailure(err != nullptr);
  if (first == ranks.size()) return;
  if (first == ranks.rank()) std::rethrow_exception(err);
  throw OtherRankFailed();
}

// A private folder of a rank other than 0 (its stages write their files there), removed at the end.
struct ScratchFolder {
  std::string path;
  ScratchFolder() = default;
  explicit ScratchFolder(int rank) {
    namespace fs = std::filesystem;
    path = (fs::temp_directory_path() /
            ("armstudy-rank" + std::to_string(rank) + "-" + std::to_string(::getpid())))
               .string();
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchFolder() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove_all(path, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

// The runner the stages see: the run's runner, timed. Its seconds are the part of the run that a
// distributed run shares among its ranks (unit batches and shared loops, their exchanges included);
// the rest of the run's wall time every rank does alone (manifest timings
// "units_and_shared_loops_s" and "run_s", docs/distributed.md "Unit costs"). Nested runs (local())
// are not timed again.
class TimedUnitRunner final : public UnitRunner {
 public:
  // `into`: the runner whose seconds this one's count into (a rank group's runner); null: its own.
  explicit TimedUnitRunner(const UnitRunner& inner, const TimedUnitRunner* into = nullptr)
      : UnitRunner(CheckpointStore::disabled(), 1, UnitTimeRecord{}),
        inner_(inner),
        into_(into ? into : this) {}
  long run(const UnitBatch& batch) const override {
    const auto t = std::chrono::steady_clock::now();
    const long r = inner_.run(batch);
    add(t);
    return r;
  }
  void share(const SharedLoop& loop) const override {
    const auto t = std::chrono::steady_clock::now();
    inner_.share(loop);
    add(t);
  }
  const UnitRunner& local() const override { return inner_.local(); }
  // The inner runner's groups, their shared loops and exchange timed alike.
  std::unique_ptr<RankGroups> groups(const std::vector<double>& weights) const override;
  double seconds() const {
    std::lock_guard<std::mutex> g(m_);
    return seconds_;
  }

  // Counts the time since t.
  void add(std::chrono::steady_clock::time_point t) const {
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    std::lock_guard<std::mutex> g(into_->m_);
    into_->seconds_ += dt;
  }

 private:
  const UnitRunner& inner_;
  const TimedUnitRunner* into_;
  mutable std::mutex m_;
  mutable double seconds_ = 0;
};

// A rank group's runner and exchange, timed into the run's TimedUnitRunner.
class TimedGroups final : public RankGroups {
 public:
  TimedGroups(std::unique_ptr<RankGroups> inner, const TimedUnitRunner& into)
      : inner_(std::move(inner)), runner_(inner_->runner(), &into), into_(into) {
    group_of = inner_->group_of;
    mine = inner_->mine;
    sends = inner_->sends;
  }
  const UnitRunner& runner() const override { return runner_; }
  std::vector<std::string> exchange(const std::vector<std::string>& bytes) const override {
    const auto t = std::chrono::steady_clock::now();
    std::vector<std::string> all = inner_->exchange(bytes);
    into_.add(t);
    return all;
  }

 private:
  std::unique_ptr<RankGroups> inner_;
  TimedUnitRunner runner_;
  const TimedUnitRunner& into_;
};

std::unique_ptr<RankGroups> TimedUnitRunner::groups(const std::vector<double>& weights) const {
  std::unique_ptr<RankGroups> g = inner_.groups(weights);
  if (!g) return nullptr;
  return std::make_unique<TimedGroups>(std::move(g), *into_);
}

// How to open the scene (the report.html section of the scene files).
report::Document sceneReport(const Study& study) {
  report::Document doc;
  doc.heading(1, "ParaView scene")
      .paragraph(
          "`scene.py` (beside this report) opens every spatial file of this run in one ParaView "
          "view, in world metres (maps coloured by manipulability or status, robot and obstacles "
          "grey): `pvpython scene.py` (a window), `pvpython scene.py --screenshot scene.png` (a "
          "picture) or `paraview --script=scene.py`. Every file carries field data `coordinates`, "
          "`units` and, for enumerations, `legend` (docs/paraview.md).");
  if (!study.obstacles.empty())
    doc.paragraph("`scene/obstacles.vtp`: the study's " + std::to_string(study.obstacles.size()) +
                  " obstacles as surfaces (array `obstacle`, named in the field data `legend`).");
  return doc;
}

namespace fs = std::filesystem;

// One run of a study on this rank: its summary, output folder, lock, checkpoint store and pages.
struct StudyRun {
  const Study& study;
  const RunOptions& options;
  const Ranks& ranks;
  const std::chrono::steady_clock::time_point t0;
  const bool root;
  RunSummary sum;
  fs::path out;
  fs::path manifest_path;
  std::optional<OutputFolderLock> lock;
  std::optional<CheckpointStore> store;
  ScratchFolder scratch;
  std::vector<report::HtmlStage> pages;  // report.html: one section per stage
  report::Document answer;               // the study's answer and warnings (report.md, report.html)
  report::Document designs;              // each design drawn at its zero pose (report.md)
  std::vector<std::pair<std::string, StageResult>> answers;  // per stage: its answer and warnings
  std::vector<report::ViewCloud> view_clouds;                // the stages' maps for view.html
  std::vector<report::ViewSolid> view_solids;                // ... and their own obstacles
  std::string view_about, view_value_label;  // ... what they show, when not manipulability maps
  bool view_written = false;

  StudyRun(const Study& s, const RunOptions& o, const Ranks& r,
           std::chrono::steady_clock::time_point t)
      : study(s), options(o), ranks(r), t0(t), root(r.root()) {}

  // The summary's output folder, design count, threads and ranks; sets the OpenMP threads.
  void setUp() {
    sum.output_dir = (fs::path(options.output_root) / study.name).string();
    sum.designs = static_cast<int>(study.designs.size());
    sum.threads = options.threads > 0 ? options.threads : omp_get_max_threads();
    sum.ranks = ranks.size();
    if (options.threads > 0) omp_set_num_threads(options.threads);
    out = fs::path(sum.output_dir);
    manifest_path = out / "manifest.json";
  }

  // Rank 0 owns the output folder: one run per folder at a time, stale temporaries of a killed run
  // go, the checkpoint store is prepared. The other ranks attach to the store after it.
  void openOutput() {
    agreed(ranks, [&] {
      if (!root) return;
      lock.emplace(sum.output_dir);
      if (options.overwrite) {
        removePreviousResults(out);
        fs::remove_all(out / ".partial");
      } else if (fs::exists(manifest_path) && !CheckpointStore::hasPartialRun(sum.output_dir)) {
        throw InputError(
            sum.output_dir, 0, "",
            "output folder already holds the results of a complete run; pass --overwrite to "
            "replace them");
      }
      store.emplace(sum.output_dir, studyFingerprint(study), sum.resume_message);
    });
    agreed(ranks, [&] {
      if (root) return;
      std::string ignored;
      store.emplace(sum.output_dir, studyFingerprint(study), ignored);
      ScratchFolder(ranks.rank()).path.swap(scratch.path);
    });
    if (root && !sum.resume_message.empty())
      std::fprintf(stderr, "armstudy: %s\n", sum.resume_message.c_str());
  }

  // designs.json (rank 0): every design with its base and overrides; then the load timing.
  void writeDesigns() {
    if (root) {
      ordered_json designs = ordered_json::array();
      for (const auto& d : study.designs) {
        ordered_json j = modelJson(d.model);
        j["variant_of"] = d.base_name;
        ordered_json ov = ordered_json::object();
        for (const auto& [k, v] : d.overrides) ov[k] = v;
        j["overrides"] = ov;
        designs.push_back(j);
      }
      writeFileAtomic((out / "designs.json").string(), designs.dump(2) + "\n");
    }
    sum.files_written.push_back("designs.json");
    sum.timings.push_back(
        {"load_and_resolve",
         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
  }

  // Evaluation stages, in registry order; the study holds a section for each stage it runs.
  void runStages(const RunOptions& stage_options, const TimedUnitRunner& units) {
    // The other processes of a distributed run write into their scratch folder, which is removed,
    // and keep their warnings to themselves: the study's files and warnings come from rank 0.
    const std::string& stage_dir = root ? sum.output_dir : scratch.path;
    StageContext ctx{study, stage_options, stage_dir, units, sum.threads, sum.output_dir, {}};
    if (!root) ctx.warnings = [](const std::string&) {};
    try {
      for (const StudySection& section : study.sections) {
        if (options.cancelled && !ranks.distributed() && options.cancelled()) throw RunCancelled();
        StageResult r = section.stage->run(ctx, *section.settings);
        const std::vector<std::string> stray = metricsOutside(r.metrics, section.stage->name());
        ARMSTUDY_CHECK(stray.empty(), "stage '" + section.stage->name() + "' names metric '" +
                                          (stray.empty() ? "" : stray[0]) +
                                          "' outside its prefix '" + section.stage->name() + "/'");
        pages.push_back({section.stage->name(), r.files, r.reports});
        StageResult a;
        a.files = r.files;
        a.answer = r.answer;
        a.warnings = r.warnings;
        a.assumptions = r.assumptions;
        answers.emplace_back(section.stage->name(), std::move(a));
        for (report::ViewCloud& c : r.view) view_clouds.push_back(std::move(c));
        view_solids.insert(view_solids.end(), r.view_solids.begin(), r.view_solids.end());
        if (!r.view.empty() && !r.view_about.empty()) {
          view_about += (view_about.empty() ? "" : " ") + r.view_about;
          view_value_label += (view_value_label.empty() ? "" : " / ") + r.view_value_label;
        }
        sum.units_resumed += r.units_resumed;
        sum.files_written.insert(sum.files_written.end(), r.files.begin(), r.files.end());
        sum.files_written.insert(sum.files_written.end(), r.previews.begin(), r.previews.end());
        sum.timings.push_back({section.stage->timingName(), r.seconds});
        sum.timings.insert(sum.timings.end(), r.timings.begin(), r.timings.end());
        sum.counts.insert(sum.counts.end(), r.counts.begin(), r.counts.end());
        sum.metrics.merge(r.metrics);
      }
    } catch (const std::exception& e) {
      if (!ranks.distributed()) throw;
      // The other ranks may be waiting for this one: say which rank failed and end the whole job.
      std::fprintf(stderr, "armstudy: error on rank %d of %d: %s\n", ranks.rank(), ranks.size(),
                   e.what());
      std::fflush(stderr);
      ranks.abortJob(dynamic_cast<const InputError*>(&e) ? 2 : 1);
    }
  }

  // Each design at its zero pose for report.md: a stage's drawing of it (<stage>/images/
  // arm_<design>.svg), else one drawn here into designs/ (their own report.html page).
  void drawDesigns() {
    designs.heading(2, "Designs");
    Writer drawn(sum.output_dir);
    report::Document page;
    page.heading(1, "Designs")
        .paragraph(
            "The study's designs at their zero pose (those a stage's report draws are shown "
            "there).");
    for (const StudyDesign& d : study.designs) {
      const std::string file = report::zeroPoseFileName(d.model.name);
      const auto by_stage =
          std::find_if(sum.files_written.begin(), sum.files_written.end(), [&](const auto& f) {
            return f.size() > file.size() + 8 && std::count(f.begin(), f.end(), '/') == 2 &&
                   f.compare(f.size() - file.size(), file.size(), file) == 0 &&
                   f.compare(f.size() - file.size() - 8, 8, "/images/") == 0;
          });
      std::string rel = by_stage != sum.files_written.end() ? *by_stage : "";
      if (rel.empty()) {
        rel = "designs/" + file;
        drawn.text(rel, report::zeroPoseSvg(d.model));
        page.append(report::zeroPoseFigure(d.model.name, file));
      }
      designs.append(report::zeroPoseFigure(d.model.name, rel));
    }
    if (drawn.files().empty()) return;
    drawn.report("designs/report.md", std::move(page));
    pages.insert(pages.begin(), report::HtmlStage{"designs", drawn.files(), drawn.reports()});
    sum.files_written.insert(sum.files_written.end(), drawn.files().begin(), drawn.files().end());
  }

  // The ParaView scene (docs/paraview.md): the obstacles, and a pvpython script that opens every
  // spatial file of the run in one view.
  void writeScene() {
    Writer scene_out(sum.output_dir);
    if (!study.obstacles.empty()) {
      io::writeVtp(scene_out.path("scene/obstacles.vtp"), scene::obstaclePolyData(study.obstacles));
      scene_out.add("scene/obstacles.vtp");
    }
    std::vector<std::string> spatial = sum.files_written;
    spatial.insert(spatial.end(), scene_out.files().begin(), scene_out.files().end());
    scene_out.text("scene.py", scene::sceneScript(study.name, spatial));
    scene_out.report("scene/report.md", sceneReport(study));
    pages.push_back({"ParaView scene", scene_out.files(), scene_out.reports()});
    sum.files_written.insert(sum.files_written.end(), scene_out.files().begin(),
                             scene_out.files().end());
  }

  // view.html (docs/study-format.md "Outputs"): the stages' maps with the arm at its best pose and
  // the study's obstacles, when a stage gave maps; without three.js, a note and no view.
  void writeView() {
    if (view_clouds.empty()) return;
    std::string why;
    const std::string three_js = report::threeJsSource(why);
    if (three_js.empty()) {
      std::fprintf(stderr, "armstudy: no view.html: %s\n", why.c_str());
      return;
    }
    report::View3d view;
    view.title = "3-D view: study " + study.name;
    view.value_label = view_value_label.empty() ? "manipulability" : view_value_label;
    view.about = view_about;
    view.clouds = std::move(view_clouds);
    // The study's obstacles, then the stages' own ones (each name once: a stage's collision
    // obstacles include the study's).
    std::vector<report::ViewSolid> solids = report::viewSolids(study.obstacles);
    solids.insert(solids.end(), view_solids.begin(), view_solids.end());
    for (const report::ViewSolid& s : solids)
      if (std::none_of(view.solids.begin(), view.solids.end(),
                       [&](const report::ViewSolid& o) { return o.name == s.name; }))
        view.solids.push_back(s);
    writeFileAtomic((out / "view.html").string(), report::viewHtml(view, three_js));
    sum.files_written.push_back("view.html");
    view_written = true;
  }

  // The answer block: the link to the 3-D view, each stage's answer, then the warnings and the
  // assumptions the answer rests on.
  void buildAnswer() {
    const std::string shown =
        view_value_label.empty()
            ? "the maps' points, the arm at its best pose and the obstacles"
            : "the maps' points by " + view_value_label + ", the arm and the obstacles";
    if (view_written)
      answer.paragraph("**Interactive 3-D view:** [view.html](view.html) (" + shown +
                       "; drag to rotate).");
    answerSection("Answer", &StageResult::answer,
                  "No stage of this study states a comparison; the details are below.");
    answerSection("Warnings", &StageResult::warnings, "None.");
    addAssumptions();
  }

  // A section of the answer block: every stage's `lines` as "**stage:** line", or `none`.
  void answerSection(const std::string& heading, std::vector<std::string> StageResult::*lines,
                     const std::string& none) {
    std::vector<std::string> items;
    for (const auto& [stage, r] : answers)
      for (const std::string& line : r.*lines) items.push_back("**" + stage + ":** " + line);
    answer.heading(2, heading);
    if (items.empty())
      answer.paragraph(none);
    else
      answer.list(items);
  }

  // report.md: the study's question, the answer, the designs, then where the details are (each
  // stage's report).
  void writeReportMd() {
    report::Document doc;
    doc.heading(1, "Study `" + study.name + "`").append(lead()).append(answer).append(designs);
    std::vector<std::string> details;
    for (const auto& [stage, r] : answers)
      for (const std::string& f : r.files)  // the stage's own reports, one folder down
        if (f.size() > 3 && f.compare(f.size() - 3, 3, ".md") == 0 &&
            std::count(f.begin(), f.end(), '/') == 1)
          details.push_back(stage + ": [" + f + "](" + f + ")");
    details.push_back("the ParaView scene: [scene/report.md](scene/report.md)");
    doc.heading(2, "Details").list(details);
    std::string md = report::toMarkdown(doc);
    md.pop_back();  // the file ends with its last line
    writeFileAtomic((out / "report.md").string(), md);
    sum.files_written.push_back("report.md");
  }

  // The assumptions the answer rests on: the study's own, then those each stage names (each line
  // once); nothing when there are none.
  void addAssumptions() {
    std::vector<std::string> lines = study.assumptions;
    for (const auto& [stage, r] : answers)
      for (const std::string& a : r.assumptions)
        if (std::find(lines.begin(), lines.end(), a) == lines.end()) lines.push_back(a);
    if (lines.empty()) return;
    answer.heading(2, "Assumptions")
        .paragraph("The results above rest on these assumed values:")
        .list(lines);
  }

  // The study's description and question: the head of report.md and report.html.
  report::Document lead() const {
    report::Document doc;
    if (!study.description.empty()) doc.markdown(study.description + "\n\n");
    if (!study.question.empty()) doc.paragraph("**Question:** " + study.question);
    return doc;
  }

  // report.html from the stages' pages, timed.
  void writeHtml() {
    const auto html0 = std::chrono::steady_clock::now();
    writeFileAtomic((out / "report.html").string(),
                    report::htmlReport(sum.output_dir, study.name, pages, answer, lead()));
    sum.files_written.push_back("report.html");
    // Part of the serial rest that rank 0 runs alone at the end (docs/distributed.md "Unit costs").
    sum.timings.push_back(
        {"report_html",
         std::chrono::duration<double>(std::chrono::steady_clock::now() - html0).count()});
  }

  // The manifest is written last: its presence marks a complete run.
  void writeManifest(const TimedUnitRunner& units) {
    ordered_json man;
    man["armstudy_version"] = kVersion;
    man["git_revision"] = kGitRevision;
    man["study"] = study.name;
    man["study_file"] = study.file;
    ordered_json inputs = ordered_json::array();
    for (const auto& in : study.inputs) inputs.push_back({{"path", in.path}, {"hash", in.hash}});
    man["inputs"] = inputs;
    man["threads"] = sum.threads;
    if (ranks.distributed()) man["ranks"] = sum.ranks;
    man["designs"] = ordered_json::array();
    for (const auto& d : study.designs) man["designs"].push_back(d.model.name);
    if (!sum.resume_message.empty()) man["resume"] = sum.resume_message;
    if (!sum.resume_message.empty()) man["units_resumed"] = sum.units_resumed;
    sum.timings.push_back({"units_and_shared_loops", units.seconds()});
    sum.timings.push_back(
        {"run", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()});
    ordered_json tim = ordered_json::object();
    for (const auto& t : sum.timings) tim[t.stage + "_s"] = t.seconds;
    for (const auto& c : sum.counts)
      tim[c.name] = c.integer ? ordered_json(static_cast<long>(c.value)) : ordered_json(c.value);
    man["timings"] = tim;
    const std::time_t now = std::time(nullptr);
    char date[64];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    man["date"] = date;
    man["files"] = sum.files_written;
    writeFileAtomic(manifest_path.string(), man.dump(2) + "\n");
  }
};

}  // namespace

// Opens the output folder, writes designs.json, runs the stages, then (rank 0) the scene,
// report.html and the manifest; the ranks agree at each step.
RunSummary runStudy(const Study& study, const RunOptions& options, const Ranks& ranks) {
  const std::string why = options.validate();
  ARMSTUDY_CHECK(why.empty(), why);
  StudyRun run(study, options, ranks, std::chrono::steady_clock::now());
  run.setUp();
  run.openOutput();
  // In a distributed run the stages' own progress bars would show one rank's share: the runner
  // reports the whole job instead (rank 0).
  RunOptions stage_options = options;
  if (ranks.distributed()) stage_options.progress = false;
  const std::unique_ptr<UnitRunner> run_units =
      ranks.unitRunner(*run.store, run.sum.threads, options.progress, options.search_group_ranks);
  if (options.cancelled && !ranks.distributed()) run_units->setCancelled(options.cancelled);
  const TimedUnitRunner units(*run_units);
  run.writeDesigns();
  run.runStages(stage_options, units);
  // Every rank is done (its units are saved) before rank 0 marks the run complete.
  agreed(ranks, [] {});
  // Rank 0 writes the scene, report.html and, last, the manifest, which marks the run complete;
  // the other ranks wait for it. Then every rank removes the unit files it saved (in parallel:
  // one file per unit, docs/distributed.md "Checkpoints"), and rank 0 the rest of the store.
  agreed(ranks, [&] {
    if (!run.root) return;
    run.drawDesigns();
    run.writeScene();
    run.writeView();
    run.buildAnswer();
    run.writeReportMd();
    run.writeHtml();
    run.writeManifest(units);
  });
  run.store->removeSaved();
  agreed(ranks, [] {});
  if (run.root) run.store->finish();
  return std::move(run.sum);
}

StageResult runStage(const Study& study, const std::string& name, const std::string& output_dir,
                     const RunOptions& options, const CheckpointStore* store) {
  const CheckpointStore none;
  const UnitRunner units(store ? *store : none,
                         options.threads > 0 ? options.threads : omp_get_max_threads());
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const StageContext ctx{study, options, output_dir, units, threads, {}, {}};
  for (const StudySection& section : study.sections)
    if (section.stage->name() == name) return section.stage->run(ctx, *section.settings);
  ARMSTUDY_CHECK(false, "the study has no section for stage '" + name + "'");
  return {};
}

}  // namespace armstudy
