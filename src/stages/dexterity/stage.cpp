#include "stages/dexterity/stage.hpp"

#include "io/toml_reader.hpp"
#include "stages/dexterity/dexterity_io.hpp"
#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy {

namespace {

class DexterityStage final : public Stage {
 public:
  std::string name() const override { return "dexterity"; }
  std::shared_ptr<const StageSettings> read(const SectionInput& in) const override {
    const toml::table* t = in.top.table("dexterity");
    if (!t) return nullptr;
    io::TableReader r(*t, in.top.file(), "dexterity");
    return std::make_shared<SettingsOf<dexterity::DexterityOptions>>(dexterity::readDexterityOptions(r, in.designs));
  }
  StageResult run(const StageContext& ctx, const StageSettings& settings) const override {
    return dexterity::runDexterityStage(ctx, settingsAs<dexterity::DexterityOptions>(settings));
  }
};

}  // namespace

const Stage& dexterityStage() {
  static const DexterityStage stage;
  return stage;
}

}  // namespace armstudy
