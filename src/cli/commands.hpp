#pragma once
// Each CLI command is one row of the command table (commands.cpp: name, --help text and the
// function that adds its options); its action runs after parsing succeeded.
// Commands only parse arguments and call the library.
#include <CLI/CLI.hpp>
#include <functional>
#include <span>
#include <utility>

namespace armstudy::cli {

using Action = std::function<int()>;  // returns the process exit code

// Adds a command's options and arguments to its subcommand `cmd`; its callback sets `action`.
using AddCommand = void (*)(CLI::App* cmd, Action& action);

struct Command {
  const char* name;
  AddCommand add;
  const char* help;
};

// Makes `run` the action once parsing succeeded (the options are stored by then).
inline void setAction(CLI::App* cmd, Action& action, Action run) {
  cmd->callback([&action, run = std::move(run)] { action = run; });
}

// Every command, in the order --help lists them.
std::span<const Command> commands();

void addDescribeCommand(CLI::App* cmd, Action& action);
void addFkCommand(CLI::App* cmd, Action& action);
void addDrawCommand(CLI::App* cmd, Action& action);
void addRunCommand(CLI::App* cmd, Action& action);
void addBaselineCommand(CLI::App* cmd, Action& action);  // cmd_regression.cpp
void addCheckCommand(CLI::App* cmd, Action& action);
void addCompareCommand(CLI::App* cmd, Action& action);  // cmd_calibrate.cpp
void addFitCommand(CLI::App* cmd, Action& action);
void addSynthCommand(CLI::App* cmd, Action& action);
void addDynamicsCommand(CLI::App* cmd, Action& action);
void addApproachCommand(CLI::App* cmd, Action& action);
void addFitSsvCommand(CLI::App* cmd, Action& action);
void addConvertCommand(CLI::App* cmd, Action& action);

// A sampled time span of the command line (approach; synth --kind trajectory): --duration in
// (0, defaults::kMaxDuration_s], --rate in (0, defaults::kMaxSampleRate_Hz], and duration x rate
// from 1 to defaults::kMaxTrajectorySamples samples; else an InputError naming the option.
void checkSampling(double duration_s, double rate_Hz);

}  // namespace armstudy::cli
