// keel bench recovery|detection|isolation|dds|ros2|scale|guard [options]: runs keel-bench, the benchmark
// harness built from bench/ and installed beside keel (bin/keel-bench), with every argument
// after `bench`. keel itself stays a thin front end; a keel built without benchmarks says so.
#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <system_error>

#include "cli/commands.hpp"

namespace keel::cli {

void addBenchCommand(CLI::App& app, std::function<int()>& run) {
  auto* sub =
      app.add_subcommand("bench",
                         "benchmarks beside peers and the machine's floor: recovery, detection, "
                         "isolation, dds, ros2, scale; guard, the regression guard CI runs (keel bench --help)");
  sub->prefix_command();  // everything after `bench` belongs to keel-bench
  sub->set_help_flag();   // --help too
  sub->allow_extras();
  sub->callback([sub, &run] {
    auto args = sub->remaining();
    run = [args] {
      std::error_code ec;
      const auto self = std::filesystem::canonical("/proc/self/exe", ec);
      const std::string harness = (self.parent_path() / "keel-bench").string();
      if (ec || ::access(harness.c_str(), X_OK) != 0) {
        if (KEEL_WITH_BENCH)
          std::cerr << "keel bench: its harness " << harness
                    << " is missing: build it (the keel_bench target) or install keel again\n";
        else
          std::cerr << "keel bench: this keel was configured with -DKEEL_BUILD_BENCH=OFF: it has no benchmark "
                       "harness\n";
        return 2;
      }
      std::vector<std::string> argv_s{harness};
      argv_s.insert(argv_s.end(), args.begin(), args.end());
      std::vector<char*> argv;
      argv.reserve(argv_s.size() + 1);
      for (auto& a : argv_s) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(harness.c_str(), argv.data());
      const int err = errno;
      std::cerr << "keel bench: cannot run " << harness << ": " << std::generic_category().message(err) << '\n';
      return 2;
    };
  });
}

}  // namespace keel::cli
