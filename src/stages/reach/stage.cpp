#include "stages/reach/stage.hpp"

#include "stages/reach/reach_stage.hpp"

namespace armstudy {

const Stage& reachStage() {
  static const FunctionStage<ReachConfig> stage(
      "reach",
      [](const SectionInput& in) -> std::optional<ReachConfig> {
        ReachConfig cfg;
        std::vector<std::pair<std::string, std::string>> files;  // pose lists are inputs too
        readReachSection(in.top, in.study_dir, in.designs, in.obstacles, cfg, files);
        for (const auto& [f, h] : files) in.inputs.push_back({f, h});
        if (!cfg.enabled) return std::nullopt;
        return cfg;
      },
      runReachStage, "reachability");
  return stage;
}

}  // namespace armstudy
