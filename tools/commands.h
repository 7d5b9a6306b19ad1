// Subcommands of the arttrack program. Each lives in its own
// tools/arttrack_<name>.cc and registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

#include "arttrack/tracker/error.h"

namespace arttrack::cli {

// Exit codes of the arttrack program.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitRuntimeError = 1;  // bad input files, unstable physics, I/O, ...
inline constexpr int kExitUsageError = 2;    // the command line itself is wrong

// A command-line value a subcommand finds wrong after parsing (exit 2).
class UsageError : public InputError {
 public:
  using InputError::InputError;
};

// Check for --out and other folder or file names: an empty one is a usage
// error (it would silently mean the working directory).
inline CLI::Validator non_empty_name() {
  return CLI::Validator(
      [](std::string& s) -> std::string { return s.empty() ? "must not be empty" : ""; }, "NAME");
}

void register_render(CLI::App& app);
void register_run(CLI::App& app);
void register_sweep(CLI::App& app);
void register_merge(CLI::App& app);
void register_tune(CLI::App& app);
void register_export(CLI::App& app);
void register_track(CLI::App& app);
void register_bench(CLI::App& app);

}  // namespace arttrack::cli
