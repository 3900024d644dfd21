// Shared plumbing of the `ricochet` subcommands: the --json / --out contract and error exits.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/csv.hpp"  // CsvTable, write_text_file: the one CSV and text-file writer
#include "common/option_problems.hpp"

namespace ricochet::cli {

/// Options every subcommand accepts.
///  --json       print one JSON document on stdout (keys documented in docs/commands/<cmd>.md)
///                and nothing else on stdout;
///  --out FILE   write results to FILE: .csv or .h5/.hdf5 by extension, or (where the command
///                accepts it) .json: the --json document, written to FILE instead of stdout.
///  --figures DIR  (where a command draws) write SVG figures into DIR.
/// With `--out FILE.json` the parser sets `json` and leaves `out` empty: the command builds its
/// JSON document as for --json, and print_json writes it to FILE (and to stdout too when --json
/// was also given).
struct OutputOptions {
  bool json = false;
  std::string out;
  bool accepts_json_file = true;  ///< set by add_output_options
};

/// Whether `--out FILE.json` is accepted: not where --out names the command's primary artifact
/// (a report page, a campaign store, an impact set, a resumable drop table).
enum class JsonOut { kAccepted, kRefused };

/// Adds a range check to the already declared option `name` of `sub` (each value of a list
/// option): a value outside [lo, hi] stops the parse with "NAME: value V is outside [LO, HI]"
/// (a non-number: "NAME: 'V' is not a number") and exit status 2 (docs/commands/README.md,
/// "Exit status"); --help shows "in [LO, HI]".
void check_range(CLI::App* sub, const std::string& name, double lo, double hi);

/// The command line's name of each library option it binds: {"assess.repeats", "--repeats"}.
using OptionNames = std::vector<std::pair<std::string, std::string>>;

/// Refuses the first of `problems` (a library options struct's problems(), common/
/// option_problems.hpp): throws InputError("<command line>", 0, the option's command-line name
/// from `names`, the library's message), exit status 2. The library decides the ranges; the
/// command line only renames. A problem of a field `names` does not list keeps the library's
/// name (the command line set it from no option of its own).
void refuse_problems(const OptionProblems& problems, const OptionNames& names);

/// Shows the library's range of the already declared option `name` in --help ("in [1, 20]"),
/// as check_range does, without checking it: the library's problems() does (refuse_problems).
/// A value that is not a number, or a negative one for an unsigned option (CLI11 would wrap it),
/// stops the parse as check_range's does.
void show_range(CLI::App* sub, const std::string& name, const OptionRange& range);

/// A library's range of an angle in radians (FitOptions::kAlphaRad, ...) in degrees, the unit of
/// the command line's angle options: the same bounds, converted here rather than restated.
OptionRange degrees(const OptionRange& radians);

/// Refuses (as refuse_problems) the first of `values` [deg] of option `name` outside
/// degrees(`radians`): "value -200 is outside [-180, 180]" in the option's own unit.
void refuse_degrees(const std::string& name, const std::vector<double>& values,
                    const OptionRange& radians);

/// Adds --json and --out to a subcommand.
void add_output_options(CLI::App* sub, OutputOptions& options,
                        JsonOut json_out = JsonOut::kAccepted);
/// The program's version (CMake's PROJECT_VERSION).
inline constexpr const char* kVersion = RICOCHET_VERSION;

/// Records the subcommand being run ("montecarlo", "dem impact") and its parser, for stamp_json.
/// main.cpp sets it before each subcommand parses its options.
void set_current_command(std::string command, const CLI::App* parser = nullptr);

/// The provenance of the files the current subcommand reads: for every value of its options and
/// positional arguments that names an existing regular file (except the files it writes: --out,
/// --write-model, --truth), {"option", "file", "bytes", "fnv1a64"} (common/provenance.hpp), in
/// option order, each file once.
nlohmann::json input_files();

/// `doc` with "command" (the subcommand run), "version" and "input_files" (input_files()) added,
/// unless it has them (an object; anything else is returned as is): every JSON document the
/// program emits goes through it.
nlohmann::json stamp_json(nlohmann::json doc);
/// Prints stamp_json(doc) pretty on stdout (used when --json is given). After `--out FILE.json`:
/// writes it to FILE (whole, through a temporary file; "out" set to FILE) and prints it too only
/// if --json was given, else prints "wrote FILE".
void print_json(const nlohmann::json& doc);
/// Throws an InputError naming the option when `out` has an extension other than the allowed.
void require_extension(const std::string& option, const std::string& path,
                       std::initializer_list<const char*> allowed);
/// require_extension for --out: the refusal lists `allowed` and, where the command accepts it,
/// .json. An empty --out is accepted (the caller decides whether --out is required).
void require_out_extension(const OutputOptions& options,
                           std::initializer_list<const char*> allowed);

// One registration function per subcommand, called in order by main.cpp (explicit registry).
void add_stats_command(CLI::App& app);
void add_paired_command(CLI::App& app);
void add_reconstruct_command(CLI::App& app);
void add_transfer_command(CLI::App& app);
void add_effects_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_calibrate_command(CLI::App& app);
void add_montecarlo_command(CLI::App& app);
void add_sobol_command(CLI::App& app);
void add_synth_command(CLI::App& app);
void add_diagnose_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_ladder_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_dem_command(CLI::App& app);
/// `dem drop` (cmd_dem_drop.cpp), added to the `dem` subcommand by add_dem_command.
void add_dem_drop_command(CLI::App& dem);
/// `dem repose` (cmd_dem_drop.cpp), added to the `dem` subcommand by add_dem_command.
void add_dem_repose_command(CLI::App& dem);
void add_upscale_command(CLI::App& app);
void add_calibrate_grains_command(CLI::App& app);
/// In a build without LIGGGHTS (cmd_without_liggghts.cpp): `dem`, `upscale` and
/// `calibrate-grains` as subcommands that exit with status 1 saying how to get LIGGGHTS.
void add_without_liggghts_commands(CLI::App& app);
std::string without_liggghts_message(const std::string& command);

}  // namespace ricochet::cli
