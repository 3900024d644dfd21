// `ricochet design` (cmd_design.cpp): registered by main.cpp like every subcommand.
#pragma once

#include <CLI/CLI.hpp>
#include <array>
#include <string>

#include "diagnosis/throw_design.hpp"

namespace ricochet::cli {

void add_design_command(CLI::App& app);

/// Parses one --range value NAME=A:B (NAME in vin_x, vin_y, win; SI units) into `box`. Throws
/// InputError(field "--range") naming the value for a malformed one, an unknown name or a name
/// given twice; the box's rules (A <= B, vin_y's B below 0) are WideBox::problems()'s.
void parse_range(const std::string& text, diagnosis::WideBox& box, std::array<bool, 3>& given);

}  // namespace ricochet::cli
