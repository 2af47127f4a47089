#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/commands.hpp"
#include "common/defaults.hpp"
#include "common/errors.hpp"
#include "engine/run.hpp"
#include "engine/study_file.hpp"
#include "study/distributed.hpp"

namespace armstudy::cli {

void addRunCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string path;
    RunOptions opt;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("study", a->path, "Study file (TOML), e.g. studies/spraying_row.toml")
      ->required();
  cmd->add_option("--output", a->opt.output_root, "Folder that receives <study name>/")
      ->capture_default_str();
  cmd->add_option(
         "--threads", a->opt.threads,
         "OpenMP threads (0 = all cores, at most " + std::to_string(defaults::kMaxThreads) + ")")
      ->check(CLI::Range(0, defaults::kMaxThreads));
  cmd->add_flag("--overwrite", a->opt.overwrite, "Replace results already in the output folder");
  cmd->add_option(
         "--unit-size", a->opt.unit_items,
         "Work items per checkpoint unit (poses, map cells, approaches, grid points; 0 = stage "
         "defaults). Results do not depend on it")
      ->check(CLI::Range(0L, defaults::kMaxUnitItems));
  cmd->add_option(
         "--search-group-ranks", a->opt.search_group_ranks,
         "Under mpirun/srun: a grid's map searches run in groups of at least this many ranks, each "
         "group searching some of the designs (0 = every rank in every search). Results do not "
         "depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, defaults::kMaxSearchGroupRanks));
  cmd->add_option("--preview", a->opt.preview_stride,
                  "Progressive maps: before computing them, write a preview of each stem map and "
                  "reach grid on every K-th value of each axis (its chained rows or sweep, before "
                  "the map search) to dexterity/preview/ and reach/preview/ and name it on stderr "
                  "(0 = none). The other files do not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, defaults::kMaxPreviewStride));
  cmd->add_flag(
      "--json", a->json,
      "Print the run summary as JSON on stdout (study, output folder, files, timings, metrics)");
  setAction(cmd, action, [a] {
    // Under mpirun/srun every rank runs this; a plain run is the single process
    // (docs/distributed.md). Errors before the stages are reported once, by the lowest rank that
    // found them (the others end quietly); runStudy ends the whole job on an error during them.
    a->opt.on_preview = [](const std::string& file) {
      std::fprintf(stderr, "armstudy: preview %s\n", file.c_str());
      std::fflush(stderr);
    };
    const std::unique_ptr<Ranks> job = joinMpiJob();
    const Ranks& ranks = job ? *job : singleProcess();
    std::optional<Study> s;
    RunSummary sum;
    try {
      std::exception_ptr err;
      try {
        s.emplace(loadStudy(a->path));
      } catch (...) {
        err = std::current_exception();
      }
      const int first = ranks.firstFailure(err != nullptr);
      if (first == ranks.rank()) std::rethrow_exception(err);
      if (first < ranks.size()) throw OtherRankFailed();
      sum = runStudy(*s, a->opt, ranks);
    } catch (const OtherRankFailed&) {
      return 1;
    }
    if (!ranks.root()) return 0;
    if (a->json) {
      nlohmann::ordered_json j;
      j["study"] = s->name;
      j["output_dir"] = sum.output_dir;
      j["report"] = sum.output_dir + "/report.html";
      j["designs"] = sum.designs;
      j["threads"] = sum.threads;
      j["ranks"] = ranks.size();
      j["units_resumed"] = sum.units_resumed;
      if (!sum.resume_message.empty()) j["resume"] = sum.resume_message;
      nlohmann::ordered_json t = nlohmann::ordered_json::object();
      for (const auto& st : sum.timings) t[st.stage + "_s"] = st.seconds;
      j["timings"] = t;
      j["metrics"] = sum.metrics.scalars;
      j["files"] = sum.files_written;
      std::printf("%s\n", j.dump(2).c_str());
      return 0;
    }
    const std::string across =
        ranks.distributed() ? " x " + std::to_string(ranks.size()) + " ranks" : "";
    std::printf("study %s: %d design(s), %d thread(s)%s -> %s\n", s->name.c_str(), sum.designs,
                sum.threads, across.c_str(), sum.output_dir.c_str());
    for (const auto& f : sum.files_written) std::printf("  wrote %s\n", f.c_str());
    return 0;
  });
}

}  // namespace armstudy::cli
