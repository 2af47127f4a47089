#pragma once
// Each CLI command registers itself on the app; its action runs after parsing succeeded.
// Commands only parse arguments and call the library.
#include <CLI/CLI.hpp>
#include <functional>

namespace armstudy::cli {

using Action = std::function<int()>;  // returns the process exit code

void addDescribeCommand(CLI::App& app, Action& action);
void addFkCommand(CLI::App& app, Action& action);
void addRunCommand(CLI::App& app, Action& action);
void addBaselineCommand(CLI::App& app, Action& action);
void addCheckCommand(CLI::App& app, Action& action);
void addCompareCommand(CLI::App& app, Action& action);  // cmd_calibrate.cpp
void addFitCommand(CLI::App& app, Action& action);
void addSynthCommand(CLI::App& app, Action& action);
void addDynamicsCommand(CLI::App& app, Action& action);
void addApproachCommand(CLI::App& app, Action& action);
void addFitSsvCommand(CLI::App& app, Action& action);

}  // namespace armstudy::cli
