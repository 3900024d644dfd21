#include "campaign_design.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "common/error.hpp"
#include "engine/shape.hpp"
#include "fit/design.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {
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

// A finite number (found by fuzz/fuzz_campaign_toml: nan and inf were accepted as velocities,
// angles, frame rates and sampling ranges).
double number_of(const toml::node& n, const std::string& file, const std::string& field) {
  const auto v = n.value<double>();
  if (!v) throw InputError(file, line_of(n), field, "expected a number");
  if (!std::isfinite(*v)) throw InputError(file, line_of(n), field, "expected a finite number");
  return *v;
}

// Largest number of impacts a design may describe. Far beyond any LIGGGHTS campaign (an impact
// costs CPU minutes); it stops a typo such as n = 100000000 from exhausting memory while the
// design is expanded, before anything runs.
constexpr std::size_t kMaxDesignImpacts = 10000;

// Throws when a design would grow to `count` impacts (count computed without overflow).
void check_design_size(double count, const std::string& file, std::size_t line,
                       const std::string& field) {
  if (count > static_cast<double>(kMaxDesignImpacts))
    throw InputError(file, line, field,
                     fmt::format("the design would have {:.0f} impacts, more than the limit of {}: "
                                 "split it into several campaigns",
                                 count, kMaxDesignImpacts));
}

std::string string_of(const toml::node& n, const std::string& file, const std::string& field) {
  if (auto v = n.value<std::string>()) return *v;
  throw InputError(file, line_of(n), field, "expected a string");
}

// A parameter value as LIGGGHTS text.
std::string param_text(const toml::node& n, const std::string& file, const std::string& field) {
  if (n.is_string()) return *n.value<std::string>();
  if (n.is_integer()) return std::to_string(*n.value<std::int64_t>());
  if (n.is_floating_point()) return shortest_number(*n.value<double>());
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
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the design file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_campaign_design(text.str(), path, decks);
}

namespace {

// [campaign]: name, ranks per impact, cache and work folders.
void read_campaign_table(const toml::table& root, const std::string& path, CampaignDesign& d) {
  const auto* c = table_at(root, "campaign", path, "");
  if (!c) return;
  check_keys(*c, {"name", "ranks_per_impact", "cache_dir", "work_dir", "end_wall_rerun_Lx_m"}, path,
             "campaign");
  if (const auto* n = c->get("name")) d.name = string_of(*n, path, "campaign.name");
  if (const auto* n = c->get("ranks_per_impact")) {
    const auto v = n->value<std::int64_t>();
    if (!v || *v < 1)
      throw InputError(path, line_of(*n), "campaign.ranks_per_impact", "expected an integer >= 1");
    d.ranks_per_impact = static_cast<int>(*v);
  }
  if (const auto* n = c->get("cache_dir")) d.cache_dir = string_of(*n, path, "campaign.cache_dir");
  if (const auto* n = c->get("work_dir")) d.work_dir = string_of(*n, path, "campaign.work_dir");
  if (const auto* n = c->get("end_wall_rerun_Lx_m")) {
    d.end_wall_rerun_Lx_m = number_of(*n, path, "campaign.end_wall_rerun_Lx_m");
    if (!(d.end_wall_rerun_Lx_m > 0 && d.end_wall_rerun_Lx_m < 1e3))
      throw InputError(path, line_of(*n), "campaign.end_wall_rerun_Lx_m",
                       "expected a bed length in metres, > 0 and < 1000");
  }
}

// [extract]: the frame rate and window of the V_in / V_out extraction.
void read_extract_table(const toml::table& root, const std::string& path, CampaignDesign& d) {
  const auto* e = table_at(root, "extract", path, "");
  if (!e) return;
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

// What every impact of a design shares: the file, the decks, the top-level overrides (which an
// impact's own override), and the ids given so far (unique).
struct Builder {
  const std::string& path;
  const Decks& decks;
  CampaignDesign& d;
  Overrides common;
  std::set<std::string> ids;

  Overrides merged(const Overrides& own) const {
    Overrides o = common;
    for (const auto& [k, v] : own.bed) o.bed[k] = v;
    for (const auto& [k, v] : own.block) o.block[k] = v;
    for (const auto& [k, v] : own.run) o.run[k] = v;
    return o;
  }
  void add(ImpactSpec s, std::size_t line, const std::string& field) {
    if (!ids.insert(s.id).second)
      throw InputError(path, line, field, "duplicate impact id '" + s.id + "'");
    d.impacts.push_back(std::move(s));
  }
};

// [[impact]]: explicit impacts, each with its own overrides.
void read_impact_tables(const toml::table& root, Builder& b) {
  const std::string& path = b.path;
  const toml::node* list = root.get("impact");
  if (!list) return;
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
    if (!std::isfinite(s.alpha_in_rad))
      throw InputError(path, line_of(*t->get("alpha_in_deg")), where + "alpha_in_deg",
                       "angle too large");
    if (const auto* n = t->get("seed")) {
      const auto v = n->value<std::int64_t>();
      if (!v || *v < 0)
        throw InputError(path, line_of(*n), where + "seed", "expected an integer >= 0");
      s.seed = *v;
    }
    Overrides own;
    read_overrides(*t, b.decks, path, where, own);
    s.params = b.merged(own);
    b.add(std::move(s), line_of(*t), where + "id");
  }
}

// The incident states of [design], in order: the explicit list, the releases of an impact-set
// file (filtered by `where`), then the rows of a plan of throws, each row with its own shape and
// replica seed (the row index).
struct Incidents {
  std::vector<std::pair<std::string, Vel3>> states;  ///< id base and V_in
  std::vector<std::string> row_shape;                ///< empty: the design's shape
  std::vector<std::optional<std::int64_t>> row_seed;
};

Incidents read_incidents(const toml::table& g, const std::string& path, const std::string& prefix) {
  Incidents in;
  if (const auto* n = g.get("incident")) {
    const toml::array* a = n->as_array();
    if (!a || a->empty())
      throw InputError(path, line_of(*n), "design.incident", "expected a list of [vx, vy, omega]");
    for (std::size_t i = 0; i < a->size(); ++i)
      in.states.emplace_back(fmt::format("{}v{:02d}", prefix, i),
                             read_vin(*a->get(i), path, fmt::format("design.incident[{}]", i)));
  }
  if (const auto* n = g.get("incident_from")) {
    std::string file = string_of(*n, path, "design.incident_from");
    if (fs::path(file).is_relative()) file = (fs::path(path).parent_path() / file).string();
    ImpactSet set = read_impact_set(file);
    if (const auto* w = g.get("where")) {
      try {
        set = filter(set, string_of(*w, path, "design.where"));
      } catch (const InputError& e) {
        if (e.file() != "--where") throw;
        throw InputError(path, line_of(*w), "design.where",
                         e.detail() + " (term '" + e.field() + "')");
      }
    }
    for (const auto& im : set.impacts) in.states.emplace_back(prefix + im.id, im.vin);
  }
  in.row_shape.resize(in.states.size());
  in.row_seed.resize(in.states.size());
  // A plan of throws (`ricochet design --out plan.csv`): incident states read by the impact-set
  // reader (read_incident_states), each row one impact of the row's shape, replica seed = the
  // row index unless `seeds` is given.
  if (const auto* n = g.get("plan")) {
    std::string file = string_of(*n, path, "design.plan");
    if (fs::path(file).is_relative()) file = (fs::path(path).parent_path() / file).string();
    const ImpactSet plan = read_incident_states(file);
    for (std::size_t i = 0; i < plan.size(); ++i) {
      check_shape(plan.impacts[i].shape, path, line_of(*n), "design.plan");
      in.states.emplace_back(prefix + plan.impacts[i].id, plan.impacts[i].vin);
      in.row_shape.push_back(plan.impacts[i].shape);
      in.row_seed.push_back(static_cast<std::int64_t>(i));
    }
  }
  if (in.states.empty())
    throw InputError(path, line_of(g), "design", "give incident, incident_from or plan");
  return in;
}

// design.alpha_in_deg: the orientations crossed with every state (default: 0).
std::vector<double> read_alphas(const toml::table& g, const std::string& path) {
  const auto* n = g.get("alpha_in_deg");
  if (!n) return {0.0};
  const toml::array* a = n->as_array();
  if (!a || a->empty())
    throw InputError(path, line_of(*n), "design.alpha_in_deg", "expected a list of angles (deg)");
  std::vector<double> alphas;
  for (const auto& x : *a) {
    alphas.push_back(number_of(x, path, "design.alpha_in_deg"));
    if (!std::isfinite(alphas.back() * std::numbers::pi / 180.0))
      throw InputError(path, line_of(x), "design.alpha_in_deg", "angle too large");
  }
  return alphas;
}

// design.alpha_in_deg_sample: an unknown orientation (the lab triangles, paper Appendix A), one
// angle per incident state, stratified over [low, high] (a one-dimensional Latin hypercube,
// seeded), kept in the spec. Empty when not given.
std::vector<double> sample_alphas(const toml::table& g, const std::string& path,
                                  std::size_t states) {
  const auto* n = g.get("alpha_in_deg_sample");
  if (!n) return {};
  const std::string field = "design.alpha_in_deg_sample";
  const toml::table* t = n->as_table();
  if (!t) throw InputError(path, line_of(*n), field, "expected { range = [low, high], seed = N }");
  check_keys(*t, {"range", "seed"}, path, field);
  const toml::array* a = t->get("range") ? t->get("range")->as_array() : nullptr;
  if (!a || a->size() != 2)
    throw InputError(path, line_of(*n), field + ".range", "expected [low, high] in degrees");
  const double lo = number_of(*a->get(0), path, field), hi = number_of(*a->get(1), path, field);
  if (!(lo < hi)) throw InputError(path, line_of(*a), field + ".range", "expected low < high");
  if (!std::isfinite((hi - lo) * std::numbers::pi) || !std::isfinite(lo * std::numbers::pi) ||
      !std::isfinite(hi * std::numbers::pi))
    throw InputError(path, line_of(*a), field + ".range", "range too wide");
  if (g.get("alpha_in_deg"))
    throw InputError(path, line_of(*n), field,
                     "give alpha_in_deg or alpha_in_deg_sample, not both");
  std::int64_t seed = 1;
  if (const auto* x = t->get("seed")) {
    const auto v = x->value<std::int64_t>();
    if (!v || *v < 0)
      throw InputError(path, line_of(*x), field + ".seed", "expected an integer >= 0");
    seed = *v;
  }
  std::vector<double> out;
  for (double u : fit::lhs_unit_design(1, states, static_cast<std::uint64_t>(seed)))
    out.push_back(lo + (hi - lo) * u);
  return out;
}

// design.seeds: the replica seeds crossed with every state (default: one, the row's or none).
std::vector<std::optional<std::int64_t>> read_seeds(const toml::table& g, const std::string& path) {
  const auto* n = g.get("seeds");
  if (!n) return {std::nullopt};
  const toml::array* a = n->as_array();
  if (!a || a->empty())
    throw InputError(path, line_of(*n), "design.seeds", "expected a list of integers >= 0");
  std::vector<std::optional<std::int64_t>> seeds;
  for (const auto& x : *a) {
    const auto v = x.value<std::int64_t>();
    if (!v || *v < 0) throw InputError(path, line_of(x), "design.seeds", "expected integers >= 0");
    seeds.push_back(*v);
  }
  return seeds;
}

// The parameter combinations of a design and their id tags, built by vary, sample and tie.
struct Combos {
  std::vector<Overrides> overrides = {Overrides{}};
  std::vector<std::string> tags = {""};
};

// design.vary: "section.name" = [values]; the cartesian product, last key fastest.
void expand_vary(const toml::table& g, const std::string& path, const Decks& decks, Combos& c) {
  const auto* vary = table_at(g, "vary", path, "design.");
  if (!vary) return;
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
    check_design_size(static_cast<double>(c.overrides.size()) * static_cast<double>(a->size()),
                      path, line_of(v), "design.vary." + key);
    Combos next{{}, {}};
    for (std::size_t i = 0; i < c.overrides.size(); ++i)
      for (std::size_t j = 0; j < a->size(); ++j) {
        const std::string value = param_text(*a->get(j), path, "design.vary." + key);
        check_param(decks, section, name, value, path, line_of(*a->get(j)));
        Overrides o = c.overrides[i];
        (section == "bed" ? o.bed : section == "block" ? o.block : o.run)[name] = value;
        next.overrides.push_back(o);
        next.tags.push_back(c.tags[i] + fmt::format("-{}{}", name, value));
      }
    c = std::move(next);
  }
}

// design.sample: a space-filling sample over grain-scale parameters, "SECTION.NAME" = [low,
// high], a Latin hypercube of n points (fit::lhs_unit_design, seeded), crossed with the
// combinations so far. Each point is one set of grain parameters (one bed when it varies bed.*):
// the design of a surrogate model of the resolved impacts (docs/resolved-model.md,
// "Calibration").
void expand_sample(const toml::table& g, const std::string& path, const Decks& decks, Combos& c) {
  const auto* sample = table_at(g, "sample", path, "design.");
  if (!sample) return;
  std::int64_t n = 0, seed = 1;
  std::vector<std::tuple<std::string, std::string, double, double>> axes;
  for (const auto& [k, v] : *sample) {
    const std::string key(k.str());
    const std::string field = "design.sample." + key;
    if (key == "n" || key == "seed") {
      const auto x = v.value<std::int64_t>();
      if (!x || *x < (key == "n" ? 2 : 0))
        throw InputError(path, line_of(v), field,
                         key == "n" ? "expected an integer >= 2" : "expected an integer >= 0");
      (key == "n" ? n : seed) = *x;
      continue;
    }
    const auto dot = key.find('.');
    const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
    if (section != "bed" && section != "block")
      throw InputError(path, line_of(v), field,
                       "keys are n, seed or SECTION.NAME with SECTION bed or block");
    const toml::array* a = v.as_array();
    if (!a || a->size() != 2) throw InputError(path, line_of(v), field, "expected [low, high]");
    const double lo = number_of(*a->get(0), path, field), hi = number_of(*a->get(1), path, field);
    if (!(lo < hi)) throw InputError(path, line_of(v), field, "expected low < high");
    if (!std::isfinite(hi - lo)) throw InputError(path, line_of(v), field, "range too wide");
    const std::string name = key.substr(dot + 1);
    for (double x : {lo, hi})
      check_param(decks, section, name, shortest_number(x), path, line_of(v));
    axes.emplace_back(section, name, lo, hi);
  }
  if (n == 0) throw InputError(path, line_of(*sample), "design.sample.n", "missing");
  check_design_size(static_cast<double>(c.overrides.size()) * static_cast<double>(n), path,
                    line_of(*sample->get("n")), "design.sample.n");
  if (axes.empty())
    throw InputError(path, line_of(*sample), "design.sample", "no parameter to sample");
  const auto u = fit::lhs_unit_design(axes.size(), static_cast<std::size_t>(n),
                                      static_cast<std::uint64_t>(seed));
  Combos next{{}, {}};
  for (std::size_t p = 0; p < static_cast<std::size_t>(n); ++p)
    for (std::size_t i = 0; i < c.overrides.size(); ++i) {
      Overrides o = c.overrides[i];
      for (std::size_t k = 0; k < axes.size(); ++k) {
        const auto& [section, name, lo, hi] = axes[k];
        // Four significant digits: the value is the bed's cache key and the abacus's x.
        const std::string value = fmt::format("{:.4g}", lo + (hi - lo) * u[p * axes.size() + k]);
        (section == "bed" ? o.bed : o.block)[name] = value;
      }
      next.overrides.push_back(o);
      next.tags.push_back(fmt::format("-p{:02d}", p) + c.tags[i]);
    }
  c = std::move(next);
}

// design.tie: "SECTION.NAME" = "SECTION.NAME", the first takes the second's value in every
// combination, e.g. the grain-block rolling resistance tied to the grains' (the same grain shape
// rolls on the block as on a grain; docs/resolved-model.md, "Recalibration with what sand
// has"). The source must be varied or sampled.
void apply_ties(const toml::table& g, const std::string& path, const Decks& decks, Combos& c) {
  const auto* tie = table_at(g, "tie", path, "design.");
  if (!tie) return;
  const auto split = [&](const std::string& key, const std::string& field, std::size_t line) {
    const auto dot = key.find('.');
    const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
    if (section != "bed" && section != "block")
      throw InputError(path, line, field,
                       "expected SECTION.NAME with SECTION bed or block, got '" + key + "'");
    return std::pair{section, key.substr(dot + 1)};
  };
  for (const auto& [k, v] : *tie) {
    const std::string key(k.str());
    const std::string field = "design.tie." + key;
    const auto [to_section, to_name] = split(key, field, line_of(v));
    const auto from = v.value<std::string>();
    if (!from) throw InputError(path, line_of(v), field, "expected \"SECTION.NAME\"");
    const auto [from_section, from_name] = split(*from, field, line_of(v));
    for (auto& o : c.overrides) {
      const auto& src = from_section == "bed" ? o.bed : o.block;
      const auto it = src.find(from_name);
      if (it == src.end())
        throw InputError(path, line_of(v), field,
                         "'" + *from + "' is not varied or sampled in this design");
      check_param(decks, to_section, to_name, it->second, path, line_of(v));
      (to_section == "bed" ? o.bed : o.block)[to_name] = it->second;
    }
  }
}

// [design]: the product incident states x orientations x seeds x parameter combinations.
void read_design_table(const toml::table& root, Builder& b) {
  const std::string& path = b.path;
  const auto* g = table_at(root, "design", path, "");
  if (!g) return;
  check_keys(*g,
             {"shape", "incident", "incident_from", "where", "plan", "alpha_in_deg",
              "alpha_in_deg_sample", "seeds", "vary", "sample", "tie", "id_prefix"},
             path, "design");
  std::string shape = "cylinder";
  if (const auto* n = g->get("shape")) {
    shape = string_of(*n, path, "design.shape");
    check_shape(shape, path, line_of(*n), "design.shape");
  }
  std::string prefix;
  if (const auto* n = g->get("id_prefix")) prefix = string_of(*n, path, "design.id_prefix");
  const Incidents in = read_incidents(*g, path, prefix);
  const std::vector<double> alphas = read_alphas(*g, path);
  const std::vector<double> sampled_alpha = sample_alphas(*g, path, in.states.size());
  const auto seeds = read_seeds(*g, path);
  Combos combos;
  expand_vary(*g, path, b.decks, combos);
  expand_sample(*g, path, b.decks, combos);
  apply_ties(*g, path, b.decks, combos);
  check_design_size(static_cast<double>(b.d.impacts.size()) +
                        static_cast<double>(in.states.size()) *
                            static_cast<double>(sampled_alpha.empty() ? alphas.size() : 1) *
                            static_cast<double>(seeds.size()) *
                            static_cast<double>(combos.overrides.size()),
                    path, line_of(*g), "design");
  for (std::size_t inc = 0; inc < in.states.size(); ++inc)
    for (double alpha : sampled_alpha.empty() ? alphas : std::vector<double>{sampled_alpha[inc]})
      for (const auto& seed : seeds)
        for (std::size_t c = 0; c < combos.overrides.size(); ++c) {
          const auto& [base, vin] = in.states[inc];
          ImpactSpec s;
          s.id = base;
          if (alphas.size() > 1) s.id += fmt::format("-a{}", shortest_number(alpha));
          if (seed && seeds.size() > 1) s.id += fmt::format("-s{}", *seed);
          s.id += combos.tags[c];
          s.shape = in.row_shape[inc].empty() ? shape : in.row_shape[inc];
          s.vin = vin;
          s.alpha_in_rad = alpha * std::numbers::pi / 180.0;
          s.seed = seed ? seed : in.row_seed[inc];
          s.params = b.merged(combos.overrides[c]);
          b.add(std::move(s), line_of(*g), "design");
        }
}

}  // namespace

CampaignDesign parse_campaign_design(const std::string& text, const std::string& path,
                                     const Decks& decks) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, static_cast<std::size_t>(e.source().begin.line), "",
                     std::string(e.description()));
  }
  CampaignDesign d;
  d.source = path;
  d.name = fs::path(path).stem().string();
  check_keys(root, {"campaign", "extract", "bed", "block", "run", "impact", "design"}, path, "");
  read_campaign_table(root, path, d);
  read_extract_table(root, path, d);
  Builder b{path, decks, d, {}, {}};
  read_overrides(root, decks, path, "", b.common);
  read_impact_tables(root, b);
  read_design_table(root, b);
  if (d.impacts.empty())
    throw InputError(path, 0, "impact", "the design has no impact: give [[impact]] or [design]");
  return d;
}

CampaignDesign select_impacts(CampaignDesign design, const std::vector<std::string>& ids) {
  std::set<std::string> known;
  for (const ImpactSpec& s : design.impacts) known.insert(s.id);
  for (const std::string& id : ids)
    if (!known.count(id)) {
      std::string list;
      for (const ImpactSpec& s : design.impacts) list += (list.empty() ? "" : ", ") + s.id;
      throw InputError(
          "<command line>", 0, "--only",
          fmt::format("'{}' is not an impact of {} (its impacts: {})", id, design.source, list));
    }
  const std::set<std::string> wanted(ids.begin(), ids.end());
  std::erase_if(design.impacts, [&](const ImpactSpec& s) { return !wanted.count(s.id); });
  return design;
}

// ---------------------------------------------------------------- results file
}  // namespace ricochet::dem
