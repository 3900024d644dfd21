// `ricochet`: one program, one subcommand per tool. See docs/commands/ for each subcommand.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "cli_common.hpp"
#include "cmd_design.hpp"
#include "common/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Ricochet: rebound of shaped blocks on soft ground (Garcia et al. 2020, JGR Earth Surface)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("ricochet ") + ricochet::cli::kVersion);

  // Explicit registry of subcommands, in the order of the paper's analysis.
  ricochet::cli::add_stats_command(app);
  ricochet::cli::add_paired_command(app);
  ricochet::cli::add_reconstruct_command(app);
  ricochet::cli::add_transfer_command(app);
  ricochet::cli::add_effects_command(app);
  ricochet::cli::add_simulate_command(app);
  ricochet::cli::add_calibrate_command(app);
  ricochet::cli::add_montecarlo_command(app);
  ricochet::cli::add_sobol_command(app);
  ricochet::cli::add_synth_command(app);
  ricochet::cli::add_compare_command(app);
  ricochet::cli::add_diagnose_command(app);
  ricochet::cli::add_ladder_command(app);
  ricochet::cli::add_design_command(app);
  ricochet::cli::add_report_command(app);
  // The resolved model needs LIGGGHTS (RICOCHET_HAVE_LIGGGHTS, set by CMake: cli/CMakeLists.txt).
#if RICOCHET_HAVE_LIGGGHTS
  ricochet::cli::add_dem_command(app);
  ricochet::cli::add_upscale_command(app);
  ricochet::cli::add_calibrate_grains_command(app);
#else
  ricochet::cli::add_without_liggghts_commands(app);
#endif

  // Each subcommand (and sub-subcommand) records its full name before its options parse, so that
  // print_json can stamp the JSON documents with it.
  const auto name_subcommands = [](auto&& self, CLI::App* parent,
                                   const std::string& prefix) -> void {
    for (CLI::App* sub : parent->get_subcommands([](CLI::App*) { return true; })) {
      const std::string name = prefix.empty() ? sub->get_name() : prefix + " " + sub->get_name();
      sub->preparse_callback(
          [name, sub](std::size_t) { ricochet::cli::set_current_command(name, sub); });
      self(self, sub, name);
    }
  };
  name_subcommands(name_subcommands, &app, "");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with status 0; every other parse error (unknown option,
    // wrong count, value out of range) is bad input: CLI11's message, then status 2.
    const int status = app.exit(e);
    return status == 0 ? 0 : 2;
  } catch (const ricochet::InputError& e) {
    std::cerr << "ricochet: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ricochet: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
