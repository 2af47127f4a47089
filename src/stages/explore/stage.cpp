#include "stages/explore/stage.hpp"

#include "io/toml_reader.hpp"
#include "stages/explore/explore.hpp"

namespace armstudy {

const Stage& exploreStage() {
  using explore::ExploreOptions;
  static const FunctionStage<ExploreOptions> stage(
      "explore",
      [](const SectionInput& in) -> std::optional<ExploreOptions> {
        if (!in.top.table("explore")) return std::nullopt;
        return explore::readExploreOptions(in);
      },
      [](const StageContext& ctx, const ExploreOptions& o) { return explore::runExploreStage(ctx, o); });
  return stage;
}

}  // namespace armstudy
