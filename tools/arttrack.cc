// arttrack: articulated robot tracking in a MuJoCo testbed.
// Errors a user can cause are printed on one line, with a non-zero exit:
// 1 for a runtime error (a bad input file, unstable physics, I/O), 2 for a
// usage error (an unknown option, a missing or out-of-range argument, an
// output folder holding a previous run's outputs without --force, an unknown
// subcommand, none). `arttrack help [SUBCOMMAND]` prints the help; `arttrack`
// alone prints it too, as a usage error.
#include <exception>
#include <iostream>

#include "arttrack/sim/search_paths.h"
#include "arttrack/tracker/version.h"
#include "commands.h"

int main(int argc, char** argv) {
  // Files that scenes and scenarios name relative to the source tree, and the
  // default scene and scenario, are found in the tree this program was built from.
  arttrack::sim::set_search_dirs({ARTTRACK_SOURCE_DIR});
  CLI::App app{"arttrack: probabilistic articulated robot tracking and its MuJoCo testbed",
               "arttrack"};
  app.require_subcommand(1);
  // The version of the project and of the tracker library it links.
  app.set_version_flag("--version", "arttrack " ARTTRACK_VERSION);
  app.footer(
      "Exit codes: 0 success, 1 runtime error (a bad input file, unstable physics, I/O), "
      "2 usage error (a wrong subcommand, option or argument, an output folder holding a "
      "previous run's outputs without --force).\n"
      "arttrack help SUBCOMMAND (or arttrack SUBCOMMAND --help) describes a subcommand.\n");
  arttrack::cli::register_render(app);
  arttrack::cli::register_run(app);
  arttrack::cli::register_rerun(app);
  arttrack::cli::register_sweep(app);
  arttrack::cli::register_merge(app);
  arttrack::cli::register_tune(app);
  arttrack::cli::register_export(app);
  arttrack::cli::register_track(app);
  arttrack::cli::register_bench(app);
  arttrack::cli::register_help(app);
  if (argc < 2) {  // no subcommand: the list of them, as a usage error
    std::cerr << app.help();
    return arttrack::cli::kExitUsageError;
  }
  try {
    arttrack::cli::check_subcommand_name(app, argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and --version: CLI11's success; anything else is a usage error.
    return app.exit(e) == 0 ? arttrack::cli::kExitSuccess : arttrack::cli::kExitUsageError;
  } catch (const arttrack::cli::UsageError& e) {
    std::cerr << "arttrack: usage error: " << arttrack::cli::shorten_long_words(e.what()) << "\n";
    return arttrack::cli::kExitUsageError;
  } catch (const std::exception& e) {
    std::cerr << "arttrack: error: " << arttrack::cli::shorten_long_words(e.what()) << "\n";
    return arttrack::cli::kExitRuntimeError;
  }
  return arttrack::cli::kExitSuccess;
}
