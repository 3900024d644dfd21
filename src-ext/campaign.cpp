#include "campaign.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>
#include <toml++/toml.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/progress.hpp"
#include "engine/shape.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- design file

std::size_t line_of(const toml::node& n) {
  return static_cast<std::size_t>(n.source().begin.line);
}

void check_keys(const toml::table& t, const std::set<std::string>& allowed, const std::string& file,
                const std::string& where) {
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError(file, line_of(v), where.empty() ? key : where + "." + key,
                       "unknown key; known: " + list);
    }
  }
}

const toml::table* table_at(const toml::table& t, const char* key, const std::string& file,
                            const std::string& where) {
  const toml::node* n = t.get(key);
  if (!n) return nullptr;
  if (!n->is_table()) throw InputError(file, line_of(*n), where + key, "expected a table");
  return n->as_table();
}

double number_of(const toml::node& n, const std::string& file, const std::string& field) {
  if (auto v = n.value<double>()) return *v;
  throw InputError(file, line_of(n), field, "expected a number");
}

std::string string_of(const toml::node& n, const std::string& file, const std::string& field) {
  if (auto v = n.value<std::string>()) return *v;
  throw InputError(file, line_of(n), field, "expected a string");
}

// A parameter value as LIGGGHTS text.
std::string param_text(const toml::node& n, const std::string& file, const std::string& field) {
  if (n.is_string()) return *n.value<std::string>();
  if (n.is_integer()) return std::to_string(*n.value<std::int64_t>());
  if (n.is_floating_point()) return format_value(*n.value<double>());
  throw InputError(file, line_of(n), field, "expected a number or a string");
}

void read_params(const toml::table* t, const std::string& section, const Decks& decks,
                 const std::string& file, const std::string& where,
                 std::map<std::string, std::string>& into) {
  if (!t) return;
  for (const auto& [k, v] : *t) {
    const std::string name(k.str());
    const std::string value = param_text(v, file, where + name);
    check_param(decks, section, name, value, file, line_of(v));
    into[name] = value;
  }
}

void read_overrides(const toml::table& t, const Decks& decks, const std::string& file,
                    const std::string& where, Overrides& o) {
  read_params(table_at(t, "bed", file, where), "bed", decks, file, where + "bed.", o.bed);
  read_params(table_at(t, "block", file, where), "block", decks, file, where + "block.", o.block);
  read_params(table_at(t, "run", file, where), "run", decks, file, where + "run.", o.run);
}

Vel3 read_vin(const toml::node& n, const std::string& file, const std::string& field) {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 3)
    throw InputError(file, line_of(n), field, "expected [vx, vy, omega] in m/s, m/s, rad/s");
  Vel3 v{};
  for (std::size_t i = 0; i < 3; ++i) v[i] = number_of(*a->get(i), file, field);
  if (!(v[kVy] < 0)) throw InputError(file, line_of(n), field, "incident vy must be < 0");
  return v;
}

void check_shape(const std::string& shape, const std::string& file, std::size_t line,
                 const std::string& field) {
  try {
    (void)Shape::resolve(shape);
  } catch (const InputError& e) {
    throw InputError(file, line, field, e.detail());
  }
}

}  // namespace

CampaignDesign read_campaign_design(const std::string& path, const Decks& decks) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<std::size_t>(e.source().begin.line), "",
                     std::string(e.description()));
  }
  CampaignDesign d;
  d.source = path;
  d.name = fs::path(path).stem().string();
  check_keys(root, {"campaign", "extract", "bed", "block", "run", "impact", "design"}, path, "");
  if (const auto* c = table_at(root, "campaign", path, "")) {
    check_keys(*c, {"name", "ranks_per_impact", "cache_dir", "work_dir"}, path, "campaign");
    if (const auto* n = c->get("name")) d.name = string_of(*n, path, "campaign.name");
    if (const auto* n = c->get("ranks_per_impact")) {
      const auto v = n->value<std::int64_t>();
      if (!v || *v < 1)
        throw InputError(path, line_of(*n), "campaign.ranks_per_impact",
                         "expected an integer >= 1");
      d.ranks_per_impact = static_cast<int>(*v);
    }
    if (const auto* n = c->get("cache_dir"))
      d.cache_dir = string_of(*n, path, "campaign.cache_dir");
    if (const auto* n = c->get("work_dir")) d.work_dir = string_of(*n, path, "campaign.work_dir");
  }
  if (const auto* e = table_at(root, "extract", path, "")) {
    check_keys(*e, {"fps", "window"}, path, "extract");
    if (const auto* n = e->get("fps")) {
      d.extract.fps = number_of(*n, path, "extract.fps");
      if (!(d.extract.fps >= 0)) throw InputError(path, line_of(*n), "extract.fps", "must be >= 0");
    }
    if (const auto* n = e->get("window")) {
      d.extract.window = string_of(*n, path, "extract.window");
      if (d.extract.window != "ground" && d.extract.window != "force" && d.extract.window != "auto")
        throw InputError(path, line_of(*n), "extract.window", "must be ground, force or auto");
    }
  }
  Overrides common;
  read_overrides(root, decks, path, "", common);
  auto merged = [&](const Overrides& own) {
    Overrides o = common;
    for (const auto& [k, v] : own.bed) o.bed[k] = v;
    for (const auto& [k, v] : own.block) o.block[k] = v;
    for (const auto& [k, v] : own.run) o.run[k] = v;
    return o;
  };
  std::set<std::string> ids;
  auto add = [&](ImpactSpec s, std::size_t line, const std::string& field) {
    if (!ids.insert(s.id).second)
      throw InputError(path, line, field, "duplicate impact id '" + s.id + "'");
    d.impacts.push_back(std::move(s));
  };

  if (const toml::node* list = root.get("impact")) {
    const toml::array* a = list->as_array();
    if (!a) throw InputError(path, line_of(*list), "impact", "use [[impact]] tables");
    for (std::size_t i = 0; i < a->size(); ++i) {
      const std::string where = fmt::format("impact[{}].", i);
      const toml::table* t = a->get(i)->as_table();
      if (!t) throw InputError(path, line_of(*a->get(i)), "impact", "expected a table");
      check_keys(*t, {"id", "shape", "vin", "alpha_in_deg", "seed", "bed", "block", "run"}, path,
                 fmt::format("impact[{}]", i));
      ImpactSpec s;
      s.id = fmt::format("i{:03d}", i);
      if (const auto* n = t->get("id")) s.id = string_of(*n, path, where + "id");
      if (const auto* n = t->get("shape")) {
        s.shape = string_of(*n, path, where + "shape");
        check_shape(s.shape, path, line_of(*n), where + "shape");
      }
      const toml::node* vin = t->get("vin");
      if (!vin) throw InputError(path, line_of(*t), where + "vin", "missing incident state");
      s.vin = read_vin(*vin, path, where + "vin");
      if (const auto* n = t->get("alpha_in_deg"))
        s.alpha_in_rad = number_of(*n, path, where + "alpha_in_deg") * std::numbers::pi / 180.0;
      if (const auto* n = t->get("seed")) {
        const auto v = n->value<std::int64_t>();
        if (!v || *v < 0)
          throw InputError(path, line_of(*n), where + "seed", "expected an integer >= 0");
        s.seed = *v;
      }
      Overrides own;
      read_overrides(*t, decks, path, where, own);
      s.params = merged(own);
      add(std::move(s), line_of(*t), where + "id");
    }
  }

  if (const auto* g = table_at(root, "design", path, "")) {
    check_keys(*g,
               {"shape", "incident", "incident_from", "where", "alpha_in_deg", "seeds", "vary",
                "id_prefix"},
               path, "design");
    std::string shape = "cylinder";
    if (const auto* n = g->get("shape")) {
      shape = string_of(*n, path, "design.shape");
      check_shape(shape, path, line_of(*n), "design.shape");
    }
    std::string prefix;
    if (const auto* n = g->get("id_prefix")) prefix = string_of(*n, path, "design.id_prefix");
    // Incident states: explicit list and/or the releases of an impact-set file.
    std::vector<std::pair<std::string, Vel3>> incident;
    if (const auto* n = g->get("incident")) {
      const toml::array* a = n->as_array();
      if (!a || a->empty())
        throw InputError(path, line_of(*n), "design.incident",
                         "expected a list of [vx, vy, omega]");
      for (std::size_t i = 0; i < a->size(); ++i)
        incident.emplace_back(fmt::format("{}v{:02d}", prefix, i),
                              read_vin(*a->get(i), path, fmt::format("design.incident[{}]", i)));
    }
    if (const auto* n = g->get("incident_from")) {
      std::string file = string_of(*n, path, "design.incident_from");
      if (fs::path(file).is_relative()) file = (fs::path(path).parent_path() / file).string();
      ImpactSet set = read_impact_set(file);
      if (const auto* w = g->get("where")) set = filter(set, string_of(*w, path, "design.where"));
      for (const auto& im : set.impacts) incident.emplace_back(prefix + im.id, im.vin);
    }
    if (incident.empty())
      throw InputError(path, line_of(*g), "design", "give incident or incident_from");
    std::vector<double> alphas = {0.0};
    if (const auto* n = g->get("alpha_in_deg")) {
      const toml::array* a = n->as_array();
      if (!a || a->empty())
        throw InputError(path, line_of(*n), "design.alpha_in_deg",
                         "expected a list of angles (deg)");
      alphas.clear();
      for (const auto& x : *a) alphas.push_back(number_of(x, path, "design.alpha_in_deg"));
    }
    std::vector<std::optional<std::int64_t>> seeds = {std::nullopt};
    if (const auto* n = g->get("seeds")) {
      const toml::array* a = n->as_array();
      if (!a || a->empty())
        throw InputError(path, line_of(*n), "design.seeds", "expected a list of integers >= 0");
      seeds.clear();
      for (const auto& x : *a) {
        const auto v = x.value<std::int64_t>();
        if (!v || *v < 0)
          throw InputError(path, line_of(x), "design.seeds", "expected integers >= 0");
        seeds.push_back(*v);
      }
    }
    // Parameter variations: "section.name" = [values]; the cartesian product, last key fastest.
    std::vector<Overrides> combos = {Overrides{}};
    std::vector<std::string> combo_tags = {""};
    if (const auto* vary = table_at(*g, "vary", path, "design.")) {
      for (const auto& [k, v] : *vary) {
        const std::string key(k.str());
        const auto dot = key.find('.');
        const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
        if (section != "bed" && section != "block" && section != "run")
          throw InputError(path, line_of(v), "design.vary." + key,
                           "keys are SECTION.NAME with SECTION bed, block or run");
        const std::string name = key.substr(dot + 1);
        const toml::array* a = v.as_array();
        if (!a || a->empty())
          throw InputError(path, line_of(v), "design.vary." + key, "expected a list of values");
        std::vector<Overrides> next;
        std::vector<std::string> next_tags;
        for (std::size_t c = 0; c < combos.size(); ++c)
          for (std::size_t j = 0; j < a->size(); ++j) {
            const std::string value = param_text(*a->get(j), path, "design.vary." + key);
            check_param(decks, section, name, value, path, line_of(*a->get(j)));
            Overrides o = combos[c];
            (section == "bed" ? o.bed : section == "block" ? o.block : o.run)[name] = value;
            next.push_back(o);
            next_tags.push_back(combo_tags[c] + fmt::format("-{}{}", name, value));
          }
        combos = std::move(next);
        combo_tags = std::move(next_tags);
      }
    }
    for (const auto& [base, vin] : incident)
      for (double alpha : alphas)
        for (const auto& seed : seeds)
          for (std::size_t c = 0; c < combos.size(); ++c) {
            ImpactSpec s;
            s.id = base;
            if (alphas.size() > 1) s.id += fmt::format("-a{}", format_value(alpha));
            if (seed && seeds.size() > 1) s.id += fmt::format("-s{}", *seed);
            s.id += combo_tags[c];
            s.shape = shape;
            s.vin = vin;
            s.alpha_in_rad = alpha * std::numbers::pi / 180.0;
            s.seed = seed;
            s.params = merged(combos[c]);
            add(std::move(s), line_of(*g), "design");
          }
  }
  if (d.impacts.empty())
    throw InputError(path, 0, "impact", "the design has no impact: give [[impact]] or [design]");
  return d;
}

// ---------------------------------------------------------------- results file

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
          "penetration_max_m"})
      n.push_back(s);
    return n;
  }();
  return names;
}

namespace {

const char* kStringColumns[] = {"id",      "status",   "message", "shape",
                                "bed_key", "work_dir", "params"};

// Serialises writers of one campaign file across processes (flock on PATH.lock).
class FileLock {
 public:
  explicit FileLock(const std::string& path) {
    fd_ = ::open((path + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
    if (fd_ < 0) throw std::runtime_error("cannot create lock file " + path + ".lock");
    ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

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
        r.ok() ? static_cast<double>(r.reconstruction.points_after) : kNaN, r.penetration_max_m})
    v[k++] = x;
  return v;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

// Index datasets are appended one after the other: a run killed between two appends leaves them
// with different lengths. Truncate to the shortest so that they line up again.
void repair_index(h5::File& f) {
  if (!f.exists("/dem/index/id")) return;
  std::size_t n = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> dims;
  const auto values = f.exists("/dem/index/values") ? f.read_doubles("/dem/index/values", &dims)
                                                    : std::vector<double>{};
  const std::size_t columns = campaign_value_names().size();
  n = std::min(n, dims.empty() ? 0 : dims[0]);
  std::map<std::string, std::vector<std::string>> strings;
  for (const char* c : kStringColumns) {
    const std::string p = std::string("/dem/index/") + c;
    strings[c] = f.exists(p) ? f.read_strings(p) : std::vector<std::string>{};
    n = std::min(n, strings[c].size());
  }
  bool aligned = dims.empty() ? n == 0 : dims[0] == n;
  for (const auto& [c, s] : strings) aligned = aligned && s.size() == n;
  if (aligned) return;
  f.remove("/dem/index");
  if (n == 0) return;
  f.append_rows("/dem/index/values", std::span<const double>(values.data(), n * columns), columns);
  for (auto& [c, s] : strings) {
    s.resize(n);
    f.append_strings("/dem/index/" + c, s);
  }
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
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : j.dump()) h = (h ^ c) * 1099511628211ull;
  return fmt::format("r{:016x}", h);
}

void rewrite_impact_set(const std::string& path, const std::vector<CampaignEntry>& entries,
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

// Last line starting with ERROR in a LIGGGHTS screen or log file: LIGGGHTS stopped the process
// (error->all ends it with exit()). Empty when there is none: the run was killed from outside.
std::string last_error(const std::string& dir) {
  std::string found;
  for (const char* f : {"screen.txt", "log.liggghts"}) {
    std::ifstream in(fs::path(dir) / f);
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("ERROR", 0) == 0) found = line;
    if (!found.empty()) return found;
  }
  return "";
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

}  // namespace

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

std::vector<CampaignEntry> read_campaign_index(const std::string& path) {
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
    out.push_back(std::move(e));
  }
  return out;
}

void append_result(const std::string& path, const ImpactResult& r, const ImpactSpec& spec,
                   const std::string& design_name) {
  FileLock lock(path);
  {
    h5::File f(path, h5::File::Mode::kReadWrite);
    f.set_attr("/dem", "schema", "ricochet-dem-campaign-1");
    f.set_attr("/dem", "design", design_name);
    repair_index(f);
    // The track first: an index row never points at a missing track.
    const std::string tg = "/dem/tracks/" + r.id;
    if (r.track.size() > 0) {
      const auto rows = r.track.rows();
      f.write(tg, rows, {r.track.size(), Track::column_names().size()});
      f.set_attr(tg, "columns", join(Track::column_names()));
      f.set_attr(tg, "frame", "paper: x flight direction, y up, omega > 0 counter-clockwise");
    }
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
  rewrite_impact_set(path, read_campaign_index(path), design_name);
}

CampaignSummary run_campaign(const CampaignDesign& design, const Decks& decks,
                             const CampaignOptions& options, MPI_Comm world) {
  const auto start = std::chrono::steady_clock::now();
  int wrank = 0, wsize = 1;
  MPI_Comm_rank(world, &wrank);
  MPI_Comm_size(world, &wsize);
  const int k = design.ranks_per_impact;
  if (k > wsize)
    throw InputError(design.source, 0, "campaign.ranks_per_impact",
                     fmt::format("{} ranks per impact but only {} MPI ranks", k, wsize));
  const int groups = wsize / k;
  const int color = wrank < groups * k ? wrank / k : MPI_UNDEFINED;
  MPI_Comm group = MPI_COMM_NULL;
  MPI_Comm_split(world, color, wrank, &group);
  int grank = -1;
  if (group != MPI_COMM_NULL) MPI_Comm_rank(group, &grank);

  CampaignSummary summary;
  summary.groups = groups;
  // World rank 0 decides what is left to do: impacts neither in the index nor crashed.
  std::vector<int> pending;
  if (wrank == 0) {
    std::set<std::string> done;
    for (const auto& e : read_campaign_index(options.out)) done.insert(e.id);
    std::vector<std::pair<std::string, std::string>> running;
    if (fs::exists(options.out)) {
      h5::File f(options.out, h5::File::Mode::kRead);
      if (f.exists("/dem/running"))
        for (const auto& id : f.list("/dem/running"))
          running.emplace_back(id, f.attr_string("/dem/running/" + id, "work_dir"));
    }
    // An impact left "running" by a previous run: if LIGGGHTS stopped the process with an
    // error, running it again would stop this run too, so it is recorded as crashed (unless
    // --retry-crashed); if the run was killed from outside, it is simply run again.
    for (const auto& [id, dir] : running) {
      if (done.count(id)) continue;
      const auto it = std::find_if(design.impacts.begin(), design.impacts.end(),
                                   [&](const ImpactSpec& s) { return s.id == id; });
      const std::string error = last_error(dir);
      if (options.retry_crashed || error.empty() || it == design.impacts.end()) continue;
      ImpactResult r;
      r.id = id;
      r.status = "crashed";
      r.message = "LIGGGHTS stopped the previous run during this impact: " + error;
      r.work_dir = dir;
      append_result(options.out, r, *it, design.name);
      done.insert(id);
    }
    for (std::size_t i = 0; i < design.impacts.size(); ++i)
      if (!done.count(design.impacts[i].id)) pending.push_back(static_cast<int>(i));
    summary.skipped = design.impacts.size() - pending.size();
  }
  int n_pending = static_cast<int>(pending.size());
  MPI_Bcast(&n_pending, 1, MPI_INT, 0, world);
  pending.resize(static_cast<std::size_t>(n_pending));
  MPI_Bcast(pending.data(), n_pending, MPI_INT, 0, world);

  // Beds first, each built once by one group, so that no two groups build the same bed.
  std::vector<std::map<std::string, std::string>> beds;
  std::set<std::string> keys;
  for (int i : pending) {
    auto o = bed_overrides(design.impacts[static_cast<std::size_t>(i)]);
    if (keys.insert(bed_key(decks, o)).second) beds.push_back(o);
  }
  for (std::size_t j = 0; j < beds.size(); ++j)
    if (group != MPI_COMM_NULL && static_cast<int>(j % static_cast<std::size_t>(groups)) == color) {
      bool built = false;
      double bed_wall = 0;
      const BedFiles b = ensure_bed(decks, beds[j], design.cache_dir, group, &built, &bed_wall);
      if (grank == 0 && built)
        std::cerr << fmt::format("[dem] bed {}: {} grains built in {:.0f} s (group {})\n", b.key,
                                 b.grains, bed_wall, color);
    }
  MPI_Barrier(world);

  for (std::size_t n = 0; n < pending.size(); ++n) {
    if (group == MPI_COMM_NULL || static_cast<int>(n % static_cast<std::size_t>(groups)) != color)
      continue;
    const ImpactSpec& spec = design.impacts[static_cast<std::size_t>(pending[n])];
    ImpactContext ctx;
    ctx.decks = &decks;
    ctx.bed = ensure_bed(decks, bed_overrides(spec), design.cache_dir, group);
    ctx.extract = design.extract;
    ctx.work_dir = (fs::path(design.work_dir) / spec.id).string();
    const Shape shape = Shape::resolve(spec.shape);
    if (grank == 0)
      ctx.template_include = ensure_template(shape, ctx.bed, design.work_dir + "/templates");
    MPI_Barrier(group);
    if (grank != 0)
      ctx.template_include = ensure_template(shape, ctx.bed, design.work_dir + "/templates");
    std::unique_ptr<Progress> bar;
    if (wrank == 0) bar = std::make_unique<Progress>("dem " + spec.id, 1000, options.progress);
    std::size_t shown = 0;
    ctx.progress = [&](double t, double t_max) {
      if (!bar) return;
      const auto now = static_cast<std::size_t>(std::clamp(1000.0 * t / t_max, 0.0, 1000.0));
      if (now > shown) bar->advance(now - shown);
      shown = std::max(shown, now);
    };
    if (grank == 0) mark_running(options.out, spec.id, ctx.work_dir);
    ImpactResult r;
    try {
      r = run_impact(spec, ctx, group);
    } catch (const std::exception& e) {
      r.id = spec.id;
      r.status = "error";
      r.message = e.what();
      r.work_dir = ctx.work_dir;
    }
    if (bar) bar->finish();
    ++summary.ran;
    if (grank == 0) {
      append_result(options.out, r, spec, design.name);
      const auto total = read_campaign_index(options.out).size();
      std::cerr << fmt::format("[dem] {}/{} {} (group {}): {} in {:.0f} s, {}\n", total,
                               design.impacts.size(), spec.id, color, r.status, r.wall_s,
                               r.message);
    }
  }
  MPI_Barrier(world);
  unsigned long ran = summary.ran;
  MPI_Allreduce(MPI_IN_PLACE, &ran, 1, MPI_UNSIGNED_LONG, MPI_SUM, world);
  summary.ran = ran;
  if (wrank == 0) {
    summary.entries = read_campaign_index(options.out);
    // A finished campaign run again rewrites its impact set, so that a file written by an
    // older version gains the newer columns (e.g. replicate) without rerunning an impact.
    if (ran == 0 && !summary.entries.empty())
      rewrite_impact_set(options.out, summary.entries, design.name);
  }
  if (group != MPI_COMM_NULL) MPI_Comm_free(&group);
  summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace ricochet::dem
