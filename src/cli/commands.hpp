// The keel command's subcommands (docs/commands.md): one file each, registered on a CLI11 app.
// A thin front end: each parses its flags and calls src/profile, src/runtime, src/fault.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace keel::cli {

/// Registers the subcommand on `app`; `run` is set to the code to execute when it is chosen,
/// returning the process exit status.
void addRunCommand(CLI::App& app, std::function<int()>& run);
void addValidateCommand(CLI::App& app, std::function<int()>& run);
void addInspectCommand(CLI::App& app, std::function<int()>& run);
void addGraphCommand(CLI::App& app, std::function<int()>& run);
void addBenchCommand(CLI::App& app, std::function<int()>& run);
void addSoakCommand(CLI::App& app, std::function<int()>& run);
void addReportCommand(CLI::App& app, std::function<int()>& run);

}  // namespace keel::cli
