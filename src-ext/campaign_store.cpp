#include "campaign_store.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/nan.hpp"
#include "file_lock.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {}  // namespace

const std::vector<std::string>& campaign_value_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = {
        "vin_x",       "vin_y",       "win",          "vout_x",           "vout_y",
        "wout",        "alpha_in",    "penetration",  "contact_duration", "sigma_vin_x",
        "sigma_vin_y", "sigma_vin_w", "sigma_vout_x", "sigma_vout_y",     "sigma_vout_w"};
    for (const auto& e : impact_extra_names()) n.push_back(e);
    for (const char* s :
         {"wall_s", "cpu_s", "steps", "grains", "block_spheres", "dt_s", "sim_time_s",
          "rayleigh_fraction", "hertz_fraction", "force_contact_start_s", "force_contact_end_s",
          "energy_dissipated_J", "window_start_s", "window_end_s", "points_before", "points_after",
          "penetration_max_m", "block_mass_kg"})
      n.push_back(s);
    return n;
  }();
  return names;
}

namespace {

const char* kStringColumns[] = {"id",      "status",   "message", "shape",
                                "bed_key", "work_dir", "params"};

std::vector<double> entry_values(const ImpactResult& r) {
  const auto& names = campaign_value_names();
  std::vector<double> v(names.size(), kNaN);
  std::size_t k = 0;
  if (r.ok()) {
    const Impact& im = r.impact;
    for (double x : im.vin) v[k++] = x;
    for (double x : im.vout) v[k++] = x;
    v[k++] = im.alpha_in.value_or(kNaN);
    v[k++] = im.penetration.value_or(kNaN);
    v[k++] = im.contact_duration.value_or(kNaN);
    for (double x : im.sigma_vin.value_or(Vel3{kNaN, kNaN, kNaN})) v[k++] = x;
    for (double x : im.sigma_vout.value_or(Vel3{kNaN, kNaN, kNaN})) v[k++] = x;
    for (double x : im.extra) v[k++] = x;
  } else {
    k = 15 + impact_extra_names().size();
  }
  for (double x :
       {r.wall_s, r.cpu_s, static_cast<double>(r.steps), static_cast<double>(r.grains),
        static_cast<double>(r.block_spheres), r.dt_s, r.sim_time_s, r.rayleigh_fraction,
        r.hertz_fraction, r.force_contact_start_s, r.force_contact_end_s,
        r.ok() ? r.energy_dissipated_J : kNaN, r.ok() ? r.reconstruction.contact_start_s : kNaN,
        r.ok() ? r.reconstruction.contact_end_s : kNaN,
        r.ok() ? static_cast<double>(r.reconstruction.points_before) : kNaN,
        r.ok() ? static_cast<double>(r.reconstruction.points_after) : kNaN, r.penetration_max_m,
        r.block_mass_kg})
    v[k++] = x;
  return v;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

// Replaces /dem/index with `rows` (row-major, campaign_value_names() wide) and the string columns
// `strings` (kStringColumns, each as long as the rows); nothing is written for no row.
void write_index(h5::File& f, const std::vector<double>& rows,
                 const std::map<std::string, std::vector<std::string>>& strings) {
  if (f.exists("/dem/index")) f.remove("/dem/index");
  if (rows.empty()) return;
  f.append_rows("/dem/index/values", rows, campaign_value_names().size());
  f.set_attr("/dem/index/values", "columns", join(campaign_value_names()));
  for (const auto& [c, v] : strings) f.append_strings("/dem/index/" + c, v);
}

// Index datasets are appended one after the other: a run killed between two appends leaves them
// with different lengths. Truncate to the shortest so that they line up again. An index written
// before the last value columns existed (campaign_value_names() only grows at its end, e.g.
// block_mass_kg) is widened, its rows padded with NaN, so that a resumed campaign appends to it.
void repair_index(h5::File& f) {
  if (!f.exists("/dem/index/id")) return;
  std::size_t n = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> dims;
  const auto values = f.exists("/dem/index/values") ? f.read_doubles("/dem/index/values", &dims)
                                                    : std::vector<double>{};
  const std::size_t columns = campaign_value_names().size();
  const std::size_t width = dims.size() > 1 ? dims[1] : columns;
  if (width > columns)
    throw std::runtime_error(fmt::format(
        "{}: /dem/index/values has {} columns, more than the {} this ricochet knows: the file was "
        "written by a newer version",
        f.path(), width, columns));
  n = std::min(n, dims.empty() ? 0 : dims[0]);
  std::map<std::string, std::vector<std::string>> strings;
  for (const char* c : kStringColumns) {
    const std::string p = std::string("/dem/index/") + c;
    strings[c] = f.exists(p) ? f.read_strings(p) : std::vector<std::string>{};
    n = std::min(n, strings[c].size());
  }
  bool aligned = (dims.empty() ? n == 0 : dims[0] == n) && width == columns;
  for (const auto& [c, s] : strings) aligned = aligned && s.size() == n;
  if (aligned) return;
  std::vector<double> rows(n * columns, kNaN);
  for (std::size_t i = 0; i < n; ++i)
    std::copy_n(values.begin() + static_cast<long>(i * width), width,
                rows.begin() + static_cast<long>(i * columns));
  for (auto& [c, s] : strings) s.resize(n);
  write_index(f, rows, strings);
}

// Replicate label of an impact: what its spec says about the experiment, without the replica
// axes (the replica seed of the bed, the position along the bed, LIGGGHTS insertion seeds, the
// id), hashed (FNV-1a, 64 bits) into a short text. Impacts sharing it repeat one experiment:
// the diagnosis pools their scatter into the noise floor.
std::string replicate_label(const std::string& params_json) {
  nlohmann::json j = nlohmann::json::parse(params_json, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return {};
  for (const char* k : {"id", "seed", "effective"}) j.erase(k);
  for (const auto& [section, name] : {std::pair{"run", "x_impact_frac"}, std::pair{"bed", "seed"},
                                      std::pair{"run", "block_seed"}})
    if (j.contains(section) && j[section].is_object()) j[section].erase(name);
  return fmt::format("r{:016x}", fnv1a(j.dump(), kDemHashSeed));
}
}  // namespace

namespace {
// The body of rewrite_impact_set, for callers that hold the exclusive lock already.
void rewrite_impact_set_unlocked(const std::string& path, const std::vector<CampaignEntry>& entries,
                                 const std::string& design_name) {
  ImpactSet set;
  set.source = path;
  set.comments = {"Resolved (LIGGGHTS) impacts of campaign '" + design_name +
                      "', written by ricochet dem. V_in, V_out: kinematics::reconstruct on the "
                      "block track (paper section 2.3).",
                  "Frame: x horizontal (flight direction), y up, omega > 0 counter-clockwise."};
  set.extra_names = impact_extra_names();
  set.extra_units = impact_extra_units();
  const auto& names = campaign_value_names();
  auto col = [&](const CampaignEntry& e, const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return e.values[static_cast<std::size_t>(it - names.begin())];
  };
  for (const auto& e : entries) {
    if (e.status != "rebound") continue;
    Impact im;
    im.id = e.id;
    im.shape = e.shape;
    im.vin = {col(e, "vin_x"), col(e, "vin_y"), col(e, "win")};
    im.vout = {col(e, "vout_x"), col(e, "vout_y"), col(e, "wout")};
    // Optional columns are absent (not NaN) when a result does not have them.
    auto optional = [&](const std::string& name) -> std::optional<double> {
      const double v = col(e, name);
      return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
    };
    auto triple = [&](const std::string& prefix) -> std::optional<Vel3> {
      const Vel3 v = {col(e, prefix + "_x"), col(e, prefix + "_y"), col(e, prefix + "_w")};
      for (double x : v)
        if (!std::isfinite(x)) return std::nullopt;
      return v;
    };
    im.alpha_in = optional("alpha_in");
    im.penetration = optional("penetration");
    im.contact_duration = optional("contact_duration");
    im.sigma_vin = triple("sigma_vin");
    im.sigma_vout = triple("sigma_vout");
    if (std::string r = replicate_label(e.params); !r.empty()) im.replicate = std::move(r);
    for (const auto& x : set.extra_names) im.extra.push_back(col(e, x));
    set.impacts.push_back(im);
  }
  if (!set.impacts.empty()) write_impact_set_h5(set, path, "impacts");
}
}  // namespace

void rewrite_impact_set(const std::string& path, const std::vector<CampaignEntry>& entries,
                        const std::string& design_name) {
  // Exclusive: a finished campaign run again rewrites the set on world rank 0 while the other
  // ranks read the index for the end-wall reruns; without the lock rank 0's H5Fopen failed
  // outright (2026-12-02, every restart of the sand calibration with its 14 reruns pending).
  FileLock lock(path);
  rewrite_impact_set_unlocked(path, entries, design_name);
}
void mark_running(const std::string& path, const std::string& id, const std::string& work_dir) {
  FileLock lock(path);
  h5::File f(path, h5::File::Mode::kReadWrite);
  const std::string g = "/dem/running/" + id;
  f.create_group(g);
  f.set_attr(g, "work_dir", work_dir);
  f.set_attr(g, "started_unix_s",
             static_cast<double>(std::chrono::duration_cast<std::chrono::seconds>(
                                     std::chrono::system_clock::now().time_since_epoch())
                                     .count()));
  f.flush();
}

std::string spec_json(const ImpactSpec& spec) {
  nlohmann::json j;
  j["id"] = spec.id;
  j["shape"] = spec.shape;
  j["vin"] = spec.vin;
  j["alpha_in_rad"] = spec.alpha_in_rad;
  if (spec.seed) j["seed"] = *spec.seed;
  j["bed"] = spec.params.bed;
  j["block"] = spec.params.block;
  j["run"] = spec.params.run;
  return j.dump();
}

std::string params_json(const ImpactSpec& spec, const ImpactResult& r) {
  nlohmann::json j = nlohmann::json::parse(spec_json(spec));
  if (!r.bed_values.empty() || !r.block_values.empty())
    j["effective"] = {{"bed", r.bed_values}, {"block", r.block_values}};
  return j.dump();
}

namespace {

std::vector<CampaignEntry> read_index_unlocked(const std::string& path) {
  std::vector<CampaignEntry> out;
  if (!fs::exists(path)) return out;
  h5::File f(path, h5::File::Mode::kRead);
  if (!f.exists("/dem/index/id") || !f.exists("/dem/index/values")) return out;
  std::vector<std::size_t> dims;
  const auto values = f.read_doubles("/dem/index/values", &dims);
  std::map<std::string, std::vector<std::string>> s;
  std::size_t n = dims.empty() ? 0 : dims[0];
  for (const char* c : kStringColumns) {
    s[c] = f.exists(std::string("/dem/index/") + c) ? f.read_strings(std::string("/dem/index/") + c)
                                                    : std::vector<std::string>{};
    n = std::min(n, s[c].size());
  }
  const std::size_t columns = dims.size() > 1 ? dims[1] : 0;
  for (std::size_t i = 0; i < n; ++i) {
    CampaignEntry e;
    e.id = s["id"][i];
    e.status = s["status"][i];
    e.message = s["message"][i];
    e.shape = s["shape"][i];
    e.bed_key = s["bed_key"][i];
    e.work_dir = s["work_dir"][i];
    e.params = s["params"][i];
    e.values.assign(values.begin() + static_cast<long>(i * columns),
                    values.begin() + static_cast<long>((i + 1) * columns));
    // An index from before the last value columns existed: those read as NaN.
    e.values.resize(std::max(e.values.size(), campaign_value_names().size()), kNaN);
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

std::vector<CampaignEntry> read_campaign_index(const std::string& path) {
  // The data file is looked for before the lock file: a writer creates PATH.lock before PATH
  // and never removes it, so a file seen here has its lock file (or is one that no writer ever
  // locked). The other order left a window: no lock file yet, so no lock taken, then the
  // writer's new file opened while it wrote (CI, 2026-11-28: "cannot open file" once in 559).
  if (!fs::exists(path)) return {};
  FileLock lock(path, FileLock::Kind::kShared);
  return read_index_unlocked(path);
}

namespace {
constexpr const char* kBeds = "/dem/beds";
}  // namespace

void record_bed_packing(const std::string& path, const std::string& key,
                        const BedPacking& packing) {
  FileLock lock(path);
  h5::File f(path, h5::File::Mode::kReadWrite);
  const std::string g = std::string(kBeds) + "/" + key;
  if (!f.exists(g)) f.create_group(g);
  f.set_attr(g, "grains", static_cast<double>(packing.grains));
  f.set_attr(g, "grain_volume_m3", packing.grain_volume_m3);
  f.set_attr(g, "bed_volume_m3", packing.bed_volume_m3);
  f.set_attr(g, "solid_fraction", packing.solid_fraction);
  f.set_attr(g, "bulk_density_kg_m3", packing.bulk_density_kg_m3);
  f.flush();
}

std::map<std::string, BedPacking> read_bed_packings(const std::string& path) {
  std::map<std::string, BedPacking> out;
  if (!fs::exists(path)) return out;
  FileLock lock(path, FileLock::Kind::kShared);
  h5::File f(path, h5::File::Mode::kRead);
  if (!f.exists(kBeds)) return out;
  for (const auto& key : f.list(kBeds)) {
    const std::string g = std::string(kBeds) + "/" + key;
    BedPacking p;
    p.grains = static_cast<long>(f.attr_double(g, "grains"));
    p.grain_volume_m3 = f.attr_double(g, "grain_volume_m3");
    p.bed_volume_m3 = f.attr_double(g, "bed_volume_m3");
    p.solid_fraction = f.attr_double(g, "solid_fraction");
    p.bulk_density_kg_m3 = f.attr_double(g, "bulk_density_kg_m3");
    out.emplace(key, p);
  }
  return out;
}

BlockTrack read_campaign_track(const std::string& path, const std::string& id) {
  if (!fs::exists(path)) throw std::runtime_error("no campaign file " + path);
  FileLock lock(path, FileLock::Kind::kShared);
  return read_block_track(path, id);
}

void append_result(const std::string& path, const ImpactResult& r, const ImpactSpec& spec,
                   const std::string& design_name) {
  FileLock lock(path);
  // The track first: an index row never points at a missing track.
  if (r.track.size() > 0) write_block_track(path, r.id, r.track);
  {
    h5::File f(path, h5::File::Mode::kReadWrite);
    f.set_attr("/dem", "schema", "ricochet-dem-campaign-1");
    f.set_attr("/dem", "design", design_name);
    repair_index(f);
    const auto values = entry_values(r);
    f.append_rows("/dem/index/values", values, values.size());
    f.set_attr("/dem/index/values", "columns", join(campaign_value_names()));
    const std::map<std::string, std::string> strings = {
        {"id", r.id},
        {"status", r.status},
        {"message", r.message},
        {"shape", r.impact.shape.empty() ? spec.shape : r.impact.shape},
        {"bed_key", r.bed_key},
        {"work_dir", r.work_dir},
        {"params", spec_json(spec)}};
    for (const char* c : kStringColumns)
      f.append_strings(std::string("/dem/index/") + c, {strings.at(c)});
    f.remove("/dem/running/" + r.id);
    f.flush();
  }
  if (r.snapshot) write_snapshot(path, *r.snapshot);
  rewrite_impact_set_unlocked(path, read_index_unlocked(path), design_name);
}

std::vector<CampaignEntry> forget_impacts(const std::string& path,
                                          const std::vector<std::string>& ids) {
  if (!fs::exists(path)) throw InputError(path, 0, "--forget", "no such campaign file");
  FileLock lock(path);
  std::vector<CampaignEntry> kept, gone;
  std::string design;
  {
    h5::File f(path, h5::File::Mode::kReadWrite);
    repair_index(f);
    if (f.has_attr("/dem", "design")) design = f.attr_string("/dem", "design");
  }
  const std::set<std::string> wanted(ids.begin(), ids.end());
  for (auto& e : read_index_unlocked(path)) (wanted.count(e.id) ? gone : kept).push_back(e);
  for (const std::string& id : wanted)
    if (std::none_of(gone.begin(), gone.end(),
                     [&](const CampaignEntry& e) { return e.id == id; })) {
      std::string list;
      for (const auto& e : kept) list += (list.empty() ? "" : ", ") + e.id;
      throw InputError(path, 0, "--forget",
                       fmt::format("no impact '{}' in the file (its impacts: {})", id, list));
    }
  {
    h5::File f(path, h5::File::Mode::kReadWrite);
    const std::size_t columns = campaign_value_names().size();
    std::vector<double> rows;
    std::map<std::string, std::vector<std::string>> strings;
    for (const auto& e : kept) {
      rows.insert(rows.end(), e.values.begin(), e.values.begin() + static_cast<long>(columns));
      strings["id"].push_back(e.id);
      strings["status"].push_back(e.status);
      strings["message"].push_back(e.message);
      strings["shape"].push_back(e.shape);
      strings["bed_key"].push_back(e.bed_key);
      strings["work_dir"].push_back(e.work_dir);
      strings["params"].push_back(e.params);
    }
    write_index(f, rows, strings);
    for (const auto& e : gone)
      if (f.exists("/dem/tracks/" + e.id)) f.remove("/dem/tracks/" + e.id);
    if (f.exists("/impacts")) f.remove("/impacts");  // rewritten below from what is kept
    f.flush();
  }
  rewrite_impact_set_unlocked(path, kept, design);
  return gone;
}
}  // namespace ricochet::dem
