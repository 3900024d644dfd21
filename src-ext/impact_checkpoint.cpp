#include "impact_checkpoint.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/provenance.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSuffixes[] = {".restart"};

fs::path json_path(const std::string& work_dir) {
  return fs::path(work_dir) / "checkpoint.json";
}

}  // namespace

std::string checkpoint_fingerprint(const std::vector<std::pair<std::string, std::string>>& vars,
                                   const Decks& decks) {
  std::uint64_t h = fnv1a("ricochet-impact-checkpoint-1");
  for (const auto& [name, value] : vars) h = fnv1a(name + "=" + value + "\n", h);
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(decks.impact_dir))
    if (e.path().extension() == ".in") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    h = fnv1a(fs::path(f).filename().string() + "\n" + text.str(), h);
  }
  return fmt::format("{:016x}", h);
}

std::string checkpoint_prefix(const std::string& work_dir, long generation) {
  return (fs::path(work_dir) / fmt::format("checkpoint-{}", generation)).string();
}

std::string checkpoint_new_prefix(const std::string& work_dir) {
  return (fs::path(work_dir) / "checkpoint-new").string();
}

std::string checkpoint_to_json(const ImpactCheckpoint& c) {
  json overlaps = json::array();
  for (const auto& [step, v] : c.overlaps) overlaps.push_back({step, v});
  return json{{"fingerprint", c.fingerprint},
              {"generation", c.generation},
              {"step0", c.step0},
              {"first_step", c.first_step},
              {"step", c.step},
              {"t_s", c.t_s},
              {"cpu_s", c.cpu_s},
              {"wall_s", c.wall_s},
              {"rayleigh_fraction", c.rayleigh_fraction},
              {"hertz_fraction", c.hertz_fraction},
              {"track_bytes", c.track_bytes},
              {"surface_before_m", c.surface_before_m},
              {"overlaps", overlaps},
              {"deck_state", c.deck_state}}
      .dump();
}

ImpactCheckpoint checkpoint_from_json(const std::string& text) {
  const json j = json::parse(text);
  ImpactCheckpoint c;
  c.fingerprint = j.at("fingerprint").get<std::string>();
  c.generation = j.at("generation").get<long>();
  c.step0 = j.at("step0").get<long>();
  c.first_step = j.at("first_step").get<long>();
  c.step = j.at("step").get<long>();
  c.t_s = j.at("t_s").get<double>();
  c.cpu_s = j.at("cpu_s").get<double>();
  c.wall_s = j.at("wall_s").get<double>();
  c.rayleigh_fraction = j.at("rayleigh_fraction").get<double>();
  c.hertz_fraction = j.at("hertz_fraction").get<double>();
  c.track_bytes = j.at("track_bytes").get<std::uintmax_t>();
  // A profile bin without grains is NaN, which JSON writes as null.
  for (const auto& v : j.at("surface_before_m"))
    c.surface_before_m.push_back(v.is_null() ? std::numeric_limits<double>::quiet_NaN()
                                             : v.get<double>());
  for (const auto& o : j.at("overlaps"))
    c.overlaps.emplace_back(o[0].get<long>(), o[1].get<double>());
  c.deck_state = j.at("deck_state").get<std::vector<std::pair<std::string, std::string>>>();
  return c;
}

std::optional<ImpactCheckpoint> read_checkpoint(const std::string& work_dir,
                                                const std::string& fingerprint) {
  std::ifstream in(json_path(work_dir));
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  ImpactCheckpoint c;
  try {
    c = checkpoint_from_json(text.str());
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (c.fingerprint != fingerprint) return std::nullopt;
  const std::string prefix = checkpoint_prefix(work_dir, c.generation);
  for (const char* s : kSuffixes)
    if (!fs::exists(prefix + s)) return std::nullopt;
  return c;
}

void commit_checkpoint(const std::string& work_dir, const ImpactCheckpoint& c) {
  const std::string from = checkpoint_new_prefix(work_dir);
  const std::string to = checkpoint_prefix(work_dir, c.generation);
  for (const char* s : kSuffixes) fs::rename(from + s, to + s);
  const fs::path tmp = json_path(work_dir).string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << checkpoint_to_json(c) << "\n";
    out.flush();
    if (!out) throw std::runtime_error("cannot write the checkpoint " + tmp.string());
  }
  fs::rename(tmp, json_path(work_dir));
  // Only now is generation c.generation the current one: the others can go.
  const std::string keep = fs::path(to).filename().string() + ".";
  for (const auto& e : fs::directory_iterator(work_dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("checkpoint-", 0) == 0 && name.rfind(keep, 0) != 0 &&
        name.rfind("checkpoint-new.", 0) != 0) {
      std::error_code ec;
      fs::remove(e.path(), ec);
    }
  }
}

void remove_checkpoints(const std::string& work_dir) {
  std::error_code ec;
  if (!fs::is_directory(work_dir, ec)) return;
  for (const auto& e : fs::directory_iterator(work_dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("checkpoint", 0) == 0) fs::remove(e.path(), ec);
  }
}

std::vector<std::pair<std::string, std::string>> resume_variables(const ImpactCheckpoint& c,
                                                                  const std::string& work_dir) {
  const std::string prefix = checkpoint_prefix(work_dir, c.generation);
  std::vector<std::pair<std::string, std::string>> vars = {
      {"resuming", "1"},
      {"restart_in", prefix + ".restart"},
      {"resume_step0", std::to_string(c.step0)},
      {"track_mode", "append"}};
  for (const auto& [name, value] : c.deck_state) vars.emplace_back("resume_" + name, value);
  return vars;
}

}  // namespace ricochet::dem
