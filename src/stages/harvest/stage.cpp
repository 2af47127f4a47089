#include "stages/harvest/stage.hpp"

#include "io/toml_reader.hpp"
#include "stages/harvest/harvest_stage.hpp"

namespace armstudy {

namespace {

class HarvestStage final : public Stage {
 public:
  std::string name() const override { return "harvest"; }
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    const toml::table* t = in.top.table("harvest");
    if (!t) return nullptr;
    io::TableReader r(*t, in.top.file(), "harvest");
    std::vector<std::string> names;
    for (const Model* m : in.designs) names.push_back(m->name);
    auto settings = std::make_shared<SettingsOf<harvest::HarvestOptions>>(harvest::readHarvestOptions(r, names));
    r.finish();
    return settings;
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return harvest::runHarvestStage(ctx, settingsAs<harvest::HarvestOptions>(settings));
  }
};

}  // namespace

const Stage& harvestStage() {
  static const HarvestStage stage;
  return stage;
}

}  // namespace armstudy
