// Where the files Ricochet ships (data/, liggghts-inputs/) are found at run time: one rule for
// every library and program, and no path compiled in (an installed tree can be moved).
//
//   1. the environment variable, when set and not empty: RICOCHET_DATA_DIR for data/,
//      RICOCHET_LIGGGHTS_INPUTS for liggghts-inputs/;
//   2. else share/ricochet/NAME in the nearest folder, going up from the running program's
//      folder, that has it: after `cmake --install`, PREFIX/bin/ricochet finds
//      PREFIX/share/ricochet/NAME; in the build tree, BUILD/cli/ricochet and the test programs
//      under BUILD/tests/ find BUILD/share/ricochet/NAME, which configuring links to the source
//      tree's folder.
//
// docs/building.md documents the rule for users.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace ricochet {

/// The folder of the shipped files NAME ("data", "liggghts-inputs"), by the rule above with
/// `env_var` as the override. Throws std::runtime_error naming `env_var` and the folders
/// searched when none has it.
std::filesystem::path shipped_dir(std::string_view name, const char* env_var);

/// data/ (lab sets, shapes, resolved campaigns): $RICOCHET_DATA_DIR, else share/ricochet/data.
std::filesystem::path data_dir();

/// liggghts-inputs/ (the LIGGGHTS decks): $RICOCHET_LIGGGHTS_INPUTS, else
/// share/ricochet/liggghts-inputs.
std::filesystem::path liggghts_inputs_dir();

/// A file's path as a page, a table or a log shows it, the same wherever the program ran: a file
/// inside data_dir() as data/REST (e.g. data/resolved/x.h5), else one inside the working folder
/// relative to it, else the path as given. Never throws.
std::string shown_path(const std::filesystem::path& path);

}  // namespace ricochet
