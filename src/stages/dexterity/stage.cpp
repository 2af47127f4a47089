#include "stages/dexterity/stage.hpp"

#include "stages/dexterity/dexterity_io.hpp"
#include "stages/dexterity/dexterity_output.hpp"

namespace armstudy {

const Stage& dexterityStage() {
  static const auto stage = FunctionStage<dexterity::DexterityOptions>::ofTable(
      "dexterity", dexterity::readDexterityOptions, dexterity::runDexterityStage);
  return stage;
}

}  // namespace armstudy
