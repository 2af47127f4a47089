#include "stages/harvest/stage.hpp"

#include "io/toml_reader.hpp"
#include "stages/harvest/harvest_stage.hpp"

namespace armstudy {

const Stage& harvestStage() {
  using harvest::HarvestOptions;
  static const FunctionStage<HarvestOptions> stage(
      "harvest",
      [](const SectionInput& in) -> std::optional<HarvestOptions> {
        const toml::table* t = in.top.table("harvest");
        if (!t) return std::nullopt;
        io::TableReader r(*t, in.top.file(), "harvest");
        std::vector<std::string> names;
        for (const Model* m : in.designs) names.push_back(m->name);
        HarvestOptions o = harvest::readHarvestOptions(r, names);
        r.finish();
        return o;
      },
      [](const StageContext& ctx, const HarvestOptions& o) { return harvest::runHarvestStage(ctx, o); });
  return stage;
}

}  // namespace armstudy
