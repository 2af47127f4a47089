#include <cstdio>

#include "cli/commands.hpp"
#include "cli/design_options.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"

namespace armstudy::cli {

void addConvertCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string in, out;
    DesignSourceOptions src;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("IN", a->in, "Input design (.urdf or .toml)")->required();
  cmd->add_option("OUT", a->out, "Output file (.toml or .urdf)")->required();
  addDesignSourceOptions(cmd, a->src);
  setAction(cmd, action, [a] {
    const bool out_urdf = isUrdfPath(a->out);
    const bool out_toml = a->out.size() > 5 && a->out.substr(a->out.size() - 5) == ".toml";
    if (!out_urdf && !out_toml)
      throw InputError(a->out, 0, "OUT", "the output must end in .urdf or .toml");
    checkOutputPath(a->out);
    std::vector<std::string> warnings;
    UrdfInfo info;
    const Model m = loadAnyDesign(a->in, a->src.urdf(), &info, &warnings);
    for (const auto& w : warnings) std::fprintf(stderr, "note: %s\n", w.c_str());
    std::string text;
    if (out_urdf) {
      text = exportUrdf(m, info);
      UrdfOptions check;
      check.collision = false;
      check.base_link = info.base_link;
      importUrdfText(text, a->out, check);  // the export must load
    } else {
      text = designToToml(m, info);
      parseDesign(text, a->out);  // the written design must load
    }
    writeFileAtomic(a->out, text);
    std::printf("wrote %s (%s, %d joints)\n", a->out.c_str(), m.name.c_str(), m.dof());
    return 0;
  });
}

}  // namespace armstudy::cli
