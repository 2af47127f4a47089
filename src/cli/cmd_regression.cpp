// `armstudy baseline STUDY` and `armstudy check STUDY`: record a study's summary metrics and
// compare a fresh run against them with the study's tolerances (docs/regression.md).
#include <cstdio>
#include <filesystem>

#include "armstudy/version.hpp"
#include "cli/commands.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "io/files.hpp"
#include "study/regression.hpp"

namespace armstudy::cli {

namespace {
struct Args {
  std::string path;
  RunOptions opt;
  std::string json_out;
  bool all = false;
};

void addRunOptions(CLI::App* cmd, Args& a) {
  cmd->add_option("study", a.path, "Study file (TOML)")->required();
  cmd->add_option("--output", a.opt.output_root, "Folder that receives <study name>/")
      ->capture_default_str();
  cmd->add_option(
         "--threads", a.opt.threads,
         "OpenMP threads (0 = all cores, at most " + std::to_string(defaults::kMaxThreads) + ")")
      ->check(CLI::Range(0, defaults::kMaxThreads));
}
}  // namespace

void addBaselineCommand(CLI::App* cmd, Action& action) {
  auto a = std::make_shared<Args>();
  addRunOptions(cmd, *a);
  setAction(cmd, action, [a] {
    const Study s = loadStudy(a->path);
    a->opt.overwrite = true;
    const RunSummary sum = runStudy(s, a->opt);
    Baseline b;
    b.study = s.name;
    b.armstudy_version = kVersion;
    b.git_revision = kGitRevision;
    b.metrics = sum.metrics;
    writeFileAtomic(s.regression.baseline_path, baselineToJson(b));
    std::printf("baseline of study %s: %zu scalar metric(s), %zu per-pose flag set(s) -> %s\n",
                s.name.c_str(), b.metrics.scalars.size(), b.metrics.flags.size(),
                s.regression.baseline_path.c_str());
    return 0;
  });
}

void addCheckCommand(CLI::App* cmd, Action& action) {
  auto a = std::make_shared<Args>();
  addRunOptions(cmd, *a);
  cmd->add_option("--json", a->json_out, "Also write the comparison as JSON to this file");
  cmd->add_flag("--all", a->all, "List every metric, not only those that moved");
  setAction(cmd, action, [a] {
    const Study s = loadStudy(a->path);
    if (!a->json_out.empty()) checkOutputPath(a->json_out);
    if (!std::filesystem::exists(s.regression.baseline_path))
      throw InputError(s.regression.baseline_path, 0, "",
                       "no baseline recorded for study '" + s.name + "'; run `armstudy baseline " +
                           a->path + "` first");
    // Read and validate the baseline before spending time on the run.
    const Baseline b = parseBaseline(readFileOrThrow(s.regression.baseline_path),
                                     s.regression.baseline_path, s.name);
    a->opt.overwrite = true;
    const RunSummary sum = runStudy(s, a->opt);
    const CheckResult r = compareToBaseline(b, sum.metrics, s.regression);
    std::fputs(checkTable(r, !a->all).c_str(), stdout);
    if (!a->json_out.empty()) writeFileAtomic(a->json_out, checkJson(r));
    std::printf("%s\n",
                r.passed() ? "check passed" : "check FAILED: results moved beyond tolerance");
    return r.passed() ? 0 : 3;
  });
}

}  // namespace armstudy::cli
