// arttrack help [SUBCOMMAND]
//
// Prints the program's help (its subcommands and the exit codes) or a
// subcommand's, the same text as --help. A name that is no subcommand, here
// or in place of one (`arttrack rnu`), is a usage error that suggests the
// nearest subcommand when it is close: "unknown subcommand 'rnu'; did you
// mean 'run'?".
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"

namespace arttrack::cli {
namespace {

// Optimal string alignment distance: the fewest insertions, deletions,
// substitutions and swaps of neighbouring characters that turn a into b.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

const CLI::App* find_subcommand(const CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == name) return sub;
  return nullptr;
}

// "unknown subcommand 'rnu'; did you mean 'run'?": the nearest subcommand
// when at most a third of its letters (at least one) differ; of two as near,
// the one with the same first letter ('tun': tune rather than run).
std::string unknown_subcommand(const CLI::App& app, const std::string& name) {
  const std::string typed = lower(name);
  std::string nearest;
  std::size_t best = std::numeric_limits<std::size_t>::max();
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string& candidate = sub->get_name();
    const std::size_t d = edit_distance(typed, candidate);
    const std::size_t score = 2 * d + (typed.empty() || typed[0] != candidate[0] ? 1 : 0);
    if (d <= std::max<std::size_t>(1, candidate.size() / 3) && score < best)
      best = score, nearest = candidate;
  }
  return "unknown subcommand '" + name + "'; " +
         (nearest.empty() ? std::string("arttrack help lists them")
                          : "did you mean '" + nearest + "'?");
}

}  // namespace

void check_subcommand_name(const CLI::App& app, int argc, const char* const* argv) {
  // The program's own options (--help, --version) take no value, so the
  // first argument that is not an option names the subcommand.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.empty() || arg[0] == '-') continue;
    if (!find_subcommand(app, arg)) throw UsageError(unknown_subcommand(app, arg));
    return;
  }
}

void register_help(CLI::App& app) {
  auto name = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "help", "Print this help, or a subcommand's (arttrack help SUBCOMMAND, as --help)");
  cmd->add_option("subcommand", *name, "The subcommand whose help to print");
  const CLI::App* parent = &app;
  cmd->callback([parent, name] {
    // parent->help() would describe the subcommand parsed: `help` itself.
    if (name->empty()) {
      std::cout << parent->get_formatter()->make_help(parent, parent->get_name(),
                                                      CLI::AppFormatMode::Normal);
      return;
    }
    const CLI::App* sub = find_subcommand(*parent, *name);
    if (!sub) throw UsageError(unknown_subcommand(*parent, *name));
    std::cout << sub->help(parent->get_name());
  });
}

}  // namespace arttrack::cli
