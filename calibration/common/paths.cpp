#include "common/paths.hpp"

#include <cstdlib>
#include <stdexcept>
#include <string>
#include <system_error>

namespace ricochet {

namespace fs = std::filesystem;

fs::path shipped_dir(std::string_view name, const char* env_var) {
  if (const char* env = std::getenv(env_var); env && *env)
    return fs::absolute(env).lexically_normal();
  const fs::path rel = fs::path("share") / "ricochet" / fs::path(name);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec)
    throw std::runtime_error("cannot locate Ricochet's " + std::string(name) +
                             " folder: the running program's path is unknown (" + ec.message() +
                             "); set " + env_var);
  for (fs::path dir = exe.parent_path();; dir = dir.parent_path()) {
    if (fs::is_directory(dir / rel, ec)) return (dir / rel).lexically_normal();
    if (dir == dir.root_path() || dir.empty()) break;
  }
  throw std::runtime_error("cannot find Ricochet's " + std::string(name) + " folder: no " +
                           rel.string() + " above " + exe.parent_path().string() + "; set " +
                           env_var + " to it");
}

fs::path data_dir() {
  return shipped_dir("data", "RICOCHET_DATA_DIR");
}

fs::path liggghts_inputs_dir() {
  return shipped_dir("liggghts-inputs", "RICOCHET_LIGGGHTS_INPUTS");
}

}  // namespace ricochet
