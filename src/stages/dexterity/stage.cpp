#include "stages/dexterity/stage.hpp"

#include "io/toml_reader.hpp"
#include "stages/dexterity/dexterity_io.hpp"
#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy {

const Stage& dexterityStage() {
  using dexterity::DexterityOptions;
  static const FunctionStage<DexterityOptions> stage(
      "dexterity",
      [](const SectionInput& in) -> std::optional<DexterityOptions> {
        const toml::table* t = in.top.table("dexterity");
        if (!t) return std::nullopt;
        io::TableReader r(*t, in.top.file(), "dexterity");
        return dexterity::readDexterityOptions(r, in.designs);
      },
      [](const StageContext& ctx, const DexterityOptions& o) { return dexterity::runDexterityStage(ctx, o); });
  return stage;
}

}  // namespace armstudy
