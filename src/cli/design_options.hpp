#pragma once
// Options of every command that reads a design, for URDF designs (docs/design-format.md, "URDF"):
// --base LINK, --tip LINK, --package NAME=DIR (repeatable), --no-collision.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "io/urdf_io.hpp"

namespace armstudy::cli {

struct DesignSourceOptions {
  std::string base, tip;
  std::vector<std::string> packages;  // NAME=DIR
  bool no_collision = false;
  UrdfOptions urdf() const;
};
void addDesignSourceOptions(CLI::App* cmd, DesignSourceOptions& options);

}  // namespace armstudy::cli
