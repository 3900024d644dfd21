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

namespace {

// `path` relative to `base` when it lies inside it (no ".." step), else empty: by their names as
// given first (a folder reached through a link stays named by the link), then with links resolved.
fs::path inside(const fs::path& path, const fs::path& base) {
  const auto relative = [](const fs::path& p, const fs::path& b) {
    const fs::path rel = p.lexically_relative(b);
    return rel.empty() || *rel.begin() == ".." ? fs::path() : rel;
  };
  std::error_code ec;
  const fs::path a = fs::absolute(path, ec).lexically_normal();
  if (ec) return {};
  if (fs::path rel = relative(a, fs::absolute(base, ec).lexically_normal()); !ec && !rel.empty())
    return rel;
  const fs::path p = fs::weakly_canonical(path, ec);
  if (ec) return {};
  const fs::path b = fs::weakly_canonical(base, ec);
  if (ec) return {};
  return relative(p, b);
}

}  // namespace

std::string shown_path(const fs::path& path) {
  try {
    if (const fs::path rel = inside(path, data_dir()); !rel.empty())
      return (fs::path("data") / rel).string();
  } catch (const std::exception&) {
    // No shipped data folder here: fall through to the working folder.
  }
  std::error_code ec;
  if (const fs::path rel = inside(path, fs::current_path(ec)); !ec && !rel.empty())
    return rel.string();
  return path.string();
}

}  // namespace ricochet
