// keel: the command-line front end (docs/commands.md).
#include <exception>
#include <iostream>

#include "cli/commands.hpp"

int main(int argc, char** argv) try {
  CLI::App app{"keel: a component framework for robots, with fault tolerance built in"};
  app.require_subcommand(1);
  // KEEL_VERSION: the project's version, from CMakeLists.txt's project() (src/cli/CMakeLists.txt).
  app.set_version_flag("--version", "keel " KEEL_VERSION);
  std::function<int()> run;
  keel::cli::addRunCommand(app, run);
  keel::cli::addValidateCommand(app, run);
  keel::cli::addInspectCommand(app, run);
  keel::cli::addGraphCommand(app, run);
  keel::cli::addBenchCommand(app, run);
  keel::cli::addSoakCommand(app, run);
  keel::cli::addReportCommand(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return run ? run() : 2;
} catch (const std::exception& e) {
  std::cerr << "keel: " << e.what() << '\n';
  return 1;
} catch (...) {
  std::cerr << "keel: unknown exception\n";
  return 1;
}
