// armstudy: batch evaluation of robot-arm designs. This file only parses arguments and dispatches;
// the engine is the armstudy library (src/).
#include <cstdio>
#include <iostream>

#include "armstudy/version.hpp"
#include "cli/commands.hpp"
#include "cli/design_options.hpp"
#include "common/errors.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "armstudy — evaluate candidate robot-arm designs in batch.\n\n"
      "Designs are TOML kinematic parameter tables (designs/*.toml, see docs/design-format.md);\n"
      "studies name designs, variants and evaluations (studies/*.toml, docs/study-format.md).\n\n"
      "Examples:\n"
      "  armstudy describe designs/final_prototype_9dof.toml\n"
      "  armstudy fk designs/final_prototype_7dof.toml --q 0.2,0,0,0,0,0,0 --deg\n"
      "  armstudy run studies/spraying_row.toml\n"};
  app.set_version_flag("--version",
                       std::string(armstudy::kVersion) + " (" + armstudy::kGitRevision + ")");
  app.require_subcommand(1);
  // Every option's default value is shown in --help (subcommands inherit this setting).
  app.option_defaults()->always_capture_default();
  armstudy::cli::Action action;
  for (const armstudy::cli::Command& c : armstudy::cli::commands())
    c.add(app.add_subcommand(c.name, c.help), action);
  // Defaults that say nothing (an empty list, NaN = "chosen per kind", a required value) are not
  // shown.
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    for (CLI::Option* opt : sub->get_options()) {
      const std::string& d = opt->get_default_str();
      if (d == "[]" || d == "nan" || opt->get_required()) opt->default_str("");
    }
  // An unknown command: name it and list the commands (CLI11 would only say one is required).
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr,
                   "armstudy: error: unknown command '%s' (commands: %s; armstudy --help)\n",
                   argv[1], names.c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every bad command line (unknown option, out-of-range value)
    // is an input error: exit 2, like bad files.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string where = "armstudy";
    for (const CLI::App* sub : app.get_subcommands()) where += " " + sub->get_name();
    std::fprintf(stderr, "armstudy: error: %s (%s --help)\n", e.what(), where.c_str());
    return 2;
  }
  try {
    return action ? action() : 0;
  } catch (const armstudy::InputError& e) {
    std::fprintf(stderr, "armstudy: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "armstudy: error: %s\n", e.what());
    return 1;
  }
}
