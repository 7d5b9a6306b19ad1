// arttrack: articulated robot tracking in a MuJoCo testbed.
// Errors a user can cause are printed on one line, with a non-zero exit.
#include <exception>
#include <iostream>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"arttrack: probabilistic articulated robot tracking and its MuJoCo testbed"};
  app.require_subcommand(1);
  arttrack::cli::register_render(app);
  arttrack::cli::register_run(app);
  arttrack::cli::register_sweep(app);
  arttrack::cli::register_merge(app);
  arttrack::cli::register_tune(app);
  arttrack::cli::register_export(app);
  arttrack::cli::register_track(app);
  arttrack::cli::register_bench(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "arttrack: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
