// The resolved-model subcommands in a build without LIGGGHTS (RICOCHET_WITH_LIGGGHTS=OFF, or
// LIGGGHTS not found): `dem`, `upscale` and `calibrate-grains` still exist, accept any arguments
// and fail with the runtime-failure status 1 (docs/commands/README.md), saying how to get them.
#include <stdexcept>
#include <string>

#include "cli_common.hpp"

namespace ricochet::cli {

std::string without_liggghts_message(const std::string& command) {
  return "`ricochet " + command +
         "` needs LIGGGHTS, and this build of ricochet has none. Install it (apt install "
         "liggghts libliggghts-dev), then reconfigure and rebuild (cmake -S SOURCE -B BUILD "
         "-DRICOCHET_WITH_LIGGGHTS=ON && cmake --build BUILD); see docs/building.md";
}

void add_without_liggghts_commands(CLI::App& app) {
  const std::pair<const char*, const char*> commands[] = {
      {"dem", "Resolved model: LIGGGHTS sand bed + multisphere block (docs/commands/dem.md)"},
      {"upscale", "Fit the reduced engine's e_n^2, mu, mu_R to resolved (LIGGGHTS) impacts"},
      {"calibrate-grains",
       "Calibrate the resolved bed's grain parameters to measured rebounds (kriging surrogate)"}};
  for (const auto& [name, what] : commands) {
    CLI::App* sub =
        app.add_subcommand(name, std::string(what) + " [not in this build: no LIGGGHTS]");
    sub->allow_extras();  // `dem impact --alpha-deg 30 ...` reaches the message, not a parse error
    sub->callback([command = std::string(name)] {
      throw std::runtime_error(without_liggghts_message(command));
    });
  }
}

}  // namespace ricochet::cli
