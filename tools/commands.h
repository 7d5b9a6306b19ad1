// Subcommands of the arttrack program. Each lives in its own
// tools/arttrack_<name>.cc and registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace arttrack::cli {

void register_render(CLI::App& app);
void register_run(CLI::App& app);
void register_sweep(CLI::App& app);
void register_merge(CLI::App& app);
void register_tune(CLI::App& app);
void register_export(CLI::App& app);
void register_track(CLI::App& app);
void register_bench(CLI::App& app);

}  // namespace arttrack::cli
