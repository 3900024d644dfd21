#include "drop_study.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <stdexcept>

#include "bed.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// drop.NAME=VALUE or repose.NAME=VALUE: a known index variable of the deck, a positive number
// (the two heights that may be 0 are the insertion's offsets).
void apply_deck_set(const std::string& section, const std::string& name, const std::string& value,
                    const std::vector<DeckParam>& known, std::map<std::string, std::string>& into) {
  if (std::none_of(known.begin(), known.end(), [&](const auto& p) { return p.name == name; })) {
    std::string names;
    for (const auto& p : known)
      names += (names.empty() ? std::string() : std::string(", ")) + p.name;
    throw InputError("<command line>", 0, section + "." + name,
                     "unknown parameter (known: " + names + ")");
  }
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (end == value.c_str() || *end != '\0' || !(v >= 0) ||
      (v == 0 && name != "y_drop_m" && name != "h_start_m"))
    throw InputError("<command line>", 0, section + "." + name,
                     "'" + value + "' must be a positive number");
  into[name] = value;
}

}  // namespace

DropStudySets parse_drop_sets(const Decks& decks, const std::vector<std::string>& sets) {
  DropStudySets out;
  const auto drop_params = drop_deck_params(decks);
  const auto repose_params = repose_deck_params(decks);
  for (const auto& s : sets) {
    const auto eq = s.find('=');
    const auto dot = s.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw InputError("<command line>", 0, "--set",
                       "expected SECTION.NAME=VALUE, got '" + s + "'");
    const std::string section = s.substr(0, dot), name = s.substr(dot + 1, eq - dot - 1),
                      value = s.substr(eq + 1);
    if (section == "bed" || section == "block") {
      Overrides ov;
      apply_set_option(decks, s, ov);
      for (const auto& [k, v] : ov.bed) out.base.bed[k] = v;
      for (const auto& [k, v] : ov.block) out.base.block[k] = v;
    } else if (section == "drop") {
      apply_deck_set(section, name, value, drop_params, out.base.drop);
    } else if (section == "repose") {
      apply_deck_set(section, name, value, repose_params, out.repose);
    } else {
      throw InputError("<command line>", 0, "--set " + s,
                       "section must be bed, block, drop or repose");
    }
  }
  return out;
}

json repose_to_json(const ReposeResult& r) {
  return {{"status", r.status},
          {"message", r.message},
          {"angle_deg", r.slope.angle_deg},
          {"angle_se_deg", r.slope.angle_se_deg},
          {"slope", r.slope.slope},
          {"slope_se", r.slope.slope_se},
          {"mu", std::tan(r.slope.angle_deg * std::numbers::pi / 180)},
          {"fitted_bins", r.slope.n},
          {"fitted_x_m", {r.slope.x_lo_m, r.slope.x_hi_m}},
          {"grains", r.grains},
          {"wall_s", r.wall_s},
          {"work_dir", r.work_dir},
          {"profile_x_m", r.x_m},
          {"profile_h_m", r.h_m}};
}

StudyFriction study_friction(const Decks& decks, const DropStudySets& sets,
                             const DropStudyOptions& options, const std::string& repose_path,
                             MPI_Comm comm) {
  StudyFriction f;
  if (options.mu > 0) {
    f.mu = options.mu;
    f.imposed = true;
    return f;
  }
  if (!repose_path.empty() && fs::exists(repose_path)) {
    std::ifstream in(repose_path);
    f.repose = json::parse(in);
  } else {
    const auto r = run_repose(decks, drop_bed_overrides(sets.base), sets.repose,
                              (fs::path(options.work_dir) / "repose").string(), comm);
    f.repose = repose_to_json(r);
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    if (rank == 0 && !repose_path.empty())
      write_text_file(repose_path, f.repose.dump(1) + "\n", "--out");
    if (r.status == "failed")
      throw std::runtime_error("the repose run gave no slope: " + r.message +
                               " (give --mu to impose the friction)");
  }
  f.mu = f.repose.at("mu").get<double>();
  return f;
}

DropStudyRun run_drop_study(const Decks& decks, const DropStudySets& sets,
                            const DropStudyOptions& options, const std::set<std::string>& done,
                            const DropStore* store, MPI_Comm comm,
                            const std::function<void(const DropResult&)>& on_drop) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  DropStudyRun run;
  // No seeds: one replica with the decks' own seeds (seed -1 in the file).
  const std::vector<long> seeds = options.seeds.empty() ? std::vector<long>{-1} : options.seeds;
  for (long seed : seeds)
    for (double h : options.heights_m) {
      DropSpec spec = sets.base;
      spec.h_drop_m = h;
      if (seed >= 0) {
        spec.id = fmt::format("h{}-s{}", shortest_number(h), seed);
        spec.seed = seed;
      } else {
        spec.id = fmt::format("h{}", shortest_number(h));
      }
      run.bed = ensure_bed(decks, drop_bed_overrides(spec), options.cache_dir, comm, nullptr,
                           nullptr, checkpoint_steps_of(decks, {}));
      if (done.count(spec.id)) continue;
      DropContext ctx;
      ctx.decks = &decks;
      ctx.bed = run.bed;
      ctx.work_dir = (fs::path(options.work_dir) / spec.id).string();
      ctx.analysis = options.analysis.analysis;
      auto r = run_drop(spec, ctx, comm);
      if (rank == 0) {
        if (on_drop) on_drop(r);
        if (store) store->append(r, seed);
      }
      run.fresh.emplace_back(std::move(r), seed);
    }
  return run;
}

std::vector<StudyDrop> study_drops(const DropStore* store, const DropStudyRun& run) {
  std::vector<StudyDrop> drops;
  if (store) {
    auto tracks = store->tracks();
    for (auto& row : store->rows()) drops.push_back({row, std::move(tracks[row.text("id")])});
  } else {
    for (const auto& [r, seed] : run.fresh) drops.push_back({drop_row(r, seed), r.track});
  }
  return drops;
}

json to_json(const StudyFriction& friction) {
  json j = {{"mu", friction.mu}, {"mu_source", friction.imposed ? "--mu" : "repose run"}};
  if (!friction.repose.is_null()) {
    json rd = friction.repose;
    rd.erase("profile_x_m");
    rd.erase("profile_h_m");
    j["repose"] = rd;
  }
  return j;
}

}  // namespace ricochet::dem
