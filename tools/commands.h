// Subcommands of the arttrack program. Each lives in its own
// tools/arttrack_<name>.cc and registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "arttrack/sim/scenario.h"
#include "arttrack/sim/scenario_runner.h"
#include "arttrack/tracker/error.h"

namespace arttrack::cli {

// Exit codes of the arttrack program.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitRuntimeError = 1;  // bad input files, unstable physics, I/O, ...
inline constexpr int kExitUsageError = 2;    // the command line itself is wrong

// Upper bounds of resource-like numbers of the command line, those of the
// matching configuration keys (scenario `runs`, particle_filter.particles,
// depth_model.width and height).
inline constexpr int kMaxRuns = 100000;
inline constexpr int kMaxEvaluations = 1000000;
inline constexpr int kMaxResolution = 4096;

// A command-line value a subcommand finds wrong after parsing (exit 2).
class UsageError : public InputError {
 public:
  using InputError::InputError;
};

// A message as the program prints it: each word (a run without spaces)
// longer than 400 characters, a value no message helper shortened
// (quote_value(), error.h) such as a file name in a std::filesystem error, is cut
// to its first kMaxQuoted characters, an ellipsis and its length. Paths of
// up to 400 characters stay whole.
inline std::string shorten_long_words(const std::string& message) {
  constexpr std::size_t kMaxWord = 400;
  std::string out;
  std::size_t start = 0;
  while (start < message.size()) {
    const std::size_t end = std::min(message.find_first_of(" \n\t", start), message.size());
    if (end - start > kMaxWord)
      out += message.substr(start, kMaxQuoted) + "... (" + std::to_string(end - start) +
             " characters)";
    else
      out += message.substr(start, end - start);
    if (end < message.size()) out += message[end];
    start = end + 1;
  }
  return out;
}

// The scenario a command simulates, as its command line gives it: the YAML
// (add_scenario_argument()), --seed (add_seed_option(); -1: the scenario's
// own) and the --set overrides in order (add_set_option()). The arguments of
// run, sweep, export and bench extend it.
struct ScenarioArgs {
  std::string scenario;
  long long seed = -1;
  std::vector<std::string> overrides;
};

// Adds the subcommand `name`, whose options fill one Args that `run` is
// called with once the command line is parsed (the callback owns it):
// returns the subcommand and the Args to bind its options to.
template <class Args>
std::pair<CLI::App*, Args*> add_command(CLI::App& app, const std::string& name,
                                        const std::string& description, void (*run)(const Args&)) {
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(name, description);
  cmd->callback([args, run] { run(*args); });
  return {cmd, args.get()};
}

// Check for --out and other folder or file names: an empty one is a usage
// error (it would silently mean the working directory).
inline CLI::Validator non_empty_name() {
  return CLI::Validator(
      [](std::string& s) -> std::string { return s.empty() ? "must not be empty" : ""; }, "NAME");
}

// An output folder holding any of `outputs` (a previous run's) is not
// overwritten without --force: a usage error naming the file.
inline void check_fresh_output(const std::filesystem::path& dir,
                               std::initializer_list<const char*> outputs, bool force) {
  if (force) return;
  for (const char* name : outputs)
    if (std::filesystem::exists(dir / name))
      throw UsageError("--out " + dir.string() + " holds a previous run's outputs (" +
                       (dir / name).string() +
                       "): choose another folder, or pass --force to overwrite them");
}

// --out of the commands that write into a folder: `help` says what goes there
// and the default, if there is one (the caller makes --out ->required() where
// there is none). An empty name is refused (non_empty_name()).
inline CLI::Option* add_out_option(CLI::App* cmd, std::string& out_dir, const std::string& help) {
  return cmd->add_option("--out", out_dir, help)->check(non_empty_name());
}

// --out and --force of the commands that refuse to overwrite a previous
// run's outputs without --force (check_fresh_output()); returns --out, as
// add_out_option() does.
inline CLI::Option* add_out_and_force_options(
    CLI::App* cmd, std::string& out_dir, bool& force, const std::string& out_help,
    const std::string& force_help = "Overwrite the outputs of a previous run in --out") {
  CLI::Option* out = add_out_option(cmd, out_dir, out_help);
  cmd->add_flag("--force", force, force_help);
  return out;
}

// The scenario YAML, the first argument of the commands that simulate one:
// required, or (`has_default`: run, bench) scenarios/default.yaml when not
// given.
inline CLI::Option* add_scenario_argument(CLI::App* cmd, std::string& scenario,
                                          bool has_default = false) {
  if (has_default)
    return cmd->add_option("scenario", scenario, "Scenario YAML (default: scenarios/default.yaml)");
  return cmd->add_option("scenario", scenario, "Scenario YAML")->required();
}

// --set of the commands that load a scenario: one `key=value` override of a
// scenario key per --set, in order.
inline void add_set_option(CLI::App* cmd, std::vector<std::string>& overrides,
                           const std::string& help =
                               "Override a scenario key, e.g. --set "
                               "duration_s=5") {
  cmd->add_option("--set", overrides, help)->allow_extra_args(false);
}

// --seed of every command that simulates (run, export, sweep, tune, bench,
// render):
// the scenario seed its runs' seeds derive from; -1 (the default) keeps the
// scenario's `seed`. `help` says what the seed drives in that command.
// --seed: any negative value is a usage error when given (the commands use
// -1 inside for "not given", which a user cannot type).
inline void add_seed_option(CLI::App* cmd, long long& seed, const std::string& help) {
  cmd->add_option("--seed", seed, help + " (default: the scenario's)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            return !s.empty() && s.front() == '-' ? "must be >= 0" : "";
          },
          "SEED >= 0"));
}

// Check for comma-separated lists (--methods a,b): an empty value or an
// empty item (",a", "a,,b", "a,") is a usage error, not "the default".
inline CLI::Validator comma_list() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (s.empty()) return "must not be empty (leave the option out for the default)";
        if (s.front() == ',' || s.back() == ',' || s.find(",,") != std::string::npos)
          return "has an empty item in '" + s + "'";
        return "";
      },
      "LIST");
}

// The items of a comma-separated option value (--methods a,b), in order;
// nothing is trimmed (comma_list() has refused empty items).
inline std::vector<std::string> split_commas(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t begin = 0; begin <= text.size();) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    if (comma > begin) out.push_back(text.substr(begin, comma - begin));
    begin = comma + 1;
  }
  return out;
}

// arttrack run's work after parsing (tools/arttrack_run.cc), shared with
// arttrack rerun: runs the scenario, writes its outputs into `out` (see
// check_fresh_output), prints the summary table.
void run_and_write(const sim::Scenario& scenario, sim::RunOptions options,
                   const std::filesystem::path& out, bool force);

// The files a command wrote into `dir`, for its closing line: "D/a, D/b and
// D/frames/ (8 files)", those in a subfolder counted (tools/arttrack_run.cc).
std::string written_files_text(const std::filesystem::path& dir,
                               const std::vector<std::filesystem::path>& files);

// A usage error when the first argument that is not an option names no
// subcommand of `app` ("unknown subcommand 'rnu'; did you mean 'run'?").
// Call before app.parse, which would only say that a subcommand is required.
void check_subcommand_name(const CLI::App& app, int argc, const char* const* argv);

void register_render(CLI::App& app);
void register_run(CLI::App& app);
void register_rerun(CLI::App& app);
void register_sweep(CLI::App& app);
void register_merge(CLI::App& app);
void register_tune(CLI::App& app);
void register_export(CLI::App& app);
void register_track(CLI::App& app);
void register_bench(CLI::App& app);
void register_help(CLI::App& app);  // arttrack help [SUBCOMMAND]

}  // namespace arttrack::cli
