// Options several subcommands share, each declared by one function here, so that its name, help
// text, range check and the parse of its value are the same on every command that takes it:
//   --vin VX,VY,W   an incident state (simulate, transfer predict, montecarlo, sobol, dem impact)
//   --where EXPR    the impact-set filter (every command that reads an impact set)
//   --figures DIR   SVG figures (every command that draws)
//   --seed K        a random seed
//   --threads N     OpenMP threads
// Defaults are not decided here: each option shows the value of the variable it is bound to, which
// the caller initialises from the library's option struct (docs/architecture.md, "Options").
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

#include "impact/impact_set.hpp"

namespace ricochet::cli {

/// Declares --vin on `sub`, bound to its text (parsed by parse_vin when the command runs, so that
/// a bad value is an InputError: exit status 2, docs/commands/README.md). `help` says what the
/// state is for and its default, if any.
CLI::Option* add_vin_option(CLI::App* sub, std::string& text, const std::string& help);

/// Parses the text of --vin: three finite numbers vx, vy, omega [m/s, m/s, rad/s] (paper frame)
/// separated by commas. `falling`: vy must be negative (a block moving down onto the ground).
/// Throws InputError(field "--vin"): "expected 3 numbers vx,vy,omega [m/s, m/s, rad/s], got
/// 'TEXT'", or "incident vy must be negative (downwards), got 'TEXT'".
Vel3 parse_vin(const std::string& text, bool falling = true);
/// `v` as --vin reads it ("2.9,-2.3,-65"), for defaults shown in help texts.
std::string format_vin(const Vel3& v);

/// Declares --where on `sub`: the impact-set filter (impact_set.hpp `filter`, applied with
/// `filter_nonempty`); `applies_to` names what it filters, e.g. "the releases of DATA".
CLI::Option* add_where_option(CLI::App* sub, std::string& where, const std::string& applies_to);

/// Declares --figures DIR on `sub`: SVG figures are written into DIR (created when missing).
CLI::Option* add_figures_option(CLI::App* sub, std::string& dir,
                                const std::string& what = "SVG figures");

/// Declares --seed on `sub`, showing the bound variable's value as the default; `of` says what
/// it seeds ("the start designs").
CLI::Option* add_seed_option(CLI::App* sub, std::uint64_t& seed, const std::string& of);
/// The same for a seed that may be absent (no default: the program's own choice).
CLI::Option* add_seed_option(CLI::App* sub, std::optional<std::uint64_t>& seed,
                             const std::string& of);

/// Declares --threads (OpenMP threads, 0 = all; checked in [0, 4096]) on `sub`.
CLI::Option* add_threads_option(CLI::App* sub, int& threads);

/// Declares --orientations (the search rule of blocks without alpha_in; 0 = the default) and
/// --polish-orientations (the refined rule; 0 = none) on `sub` (fit::AlphaOptions).
void add_orientation_options(CLI::App* sub, int& search_points, int& polish_points);

}  // namespace ricochet::cli
