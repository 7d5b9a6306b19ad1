// arttrack merge DIR... --out DIR
//
// Combines the --out folders of `arttrack sweep --shard I/N` runs (each with
// sweep.json and sweep.csv) into DIR/sweep.csv, DIR/sweep.html and
// DIR/sweep.json: byte for byte what one unsharded sweep writes. Parts of
// different sweeps, a cell in two parts or cells in none are errors.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "arttrack/sim/sweep.h"
#include "commands.h"

namespace arttrack::cli {
namespace {

namespace fs = std::filesystem;

struct MergeArgs {
  std::vector<std::string> parts;
  std::string out_dir;
};

void merge(const MergeArgs& args) {
  std::vector<fs::path> parts(args.parts.begin(), args.parts.end());
  sim::merge_sweep_parts(parts, args.out_dir);
  // Count what the merged CSV holds, as a check the user can read.
  std::ifstream csv(fs::path(args.out_dir) / "sweep.csv");
  std::size_t rows = 0, failed = 0;
  for (std::string line; std::getline(csv, line);) {
    ++rows;
    if (line.find(",failed,") != std::string::npos) ++failed;
  }
  std::cout << "merged " << parts.size() << " part(s): " << (rows ? rows - 1 : 0) << " rows ("
            << failed << " of failed cells) -> " << (fs::path(args.out_dir) / "sweep.csv").string()
            << ", " << (fs::path(args.out_dir) / "sweep.html").string() << "\n";
}

}  // namespace

void register_merge(CLI::App& app) {
  const auto [cmd, args] = add_command(
      app, "merge", "Merge the parts of a sharded sweep (arttrack sweep --shard I/N) into one",
      merge);
  cmd->add_option("parts", args->parts, "Output folders of the shard runs")->required();
  add_out_option(cmd, args->out_dir, "Folder for the merged outputs")->required();
}

}  // namespace arttrack::cli
