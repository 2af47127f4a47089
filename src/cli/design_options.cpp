#include "cli/design_options.hpp"

#include <filesystem>

#include "common/errors.hpp"

namespace armstudy::cli {

void addDesignSourceOptions(CLI::App* cmd, DesignSourceOptions& o) {
  cmd->add_option("--base", o.base,
                  "URDF designs: base link of the chain (default: the root link)");
  cmd->add_option(
      "--tip", o.tip,
      "URDF designs: tip link, also the TCP frame (default: the end of the longest chain of\n"
      "movable joints, when unique)");
  cmd->add_option("--package", o.packages,
                  "URDF designs: package://NAME/... resolves to DIR/... (NAME=DIR, repeatable;\n"
                  "otherwise the folders above the URDF file are searched)");
  cmd->add_flag("--no-collision", o.no_collision,
                "URDF designs: do not fit collision volumes to the link geometry");
}

UrdfOptions DesignSourceOptions::urdf() const {
  UrdfOptions u;
  u.base_link = base;
  u.tip_link = tip;
  for (const auto& p : packages) {
    u.packages.push_back(parsePackageOption(p, "--package"));
    const auto& [name, dir] = u.packages.back();
    if (!std::filesystem::is_directory(dir))
      throw InputError("--package", 0, "package",
                       "folder '" + dir + "' for package '" + name + "' does not exist (" +
                           std::filesystem::absolute(dir).string() + ")");
  }
  u.collision = !no_collision;
  return u;
}

}  // namespace armstudy::cli
