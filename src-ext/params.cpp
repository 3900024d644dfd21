#include "params.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "common/paths.hpp"

namespace ricochet::dem {

namespace fs = std::filesystem;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool parse_double(const std::string& text, double& v) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

const std::vector<DeckParam>& section_params(const Decks& decks, const std::string& section) {
  if (section == "bed") return decks.bed_params;
  if (section == "block") return decks.block_params;
  if (section == "run") return decks.impact_params;
  throw std::invalid_argument("unknown parameter section " + section);
}

// Names of setup.in's index variables that are wiring, not parameters: the driver sets them.
const std::set<std::string> kWiring = {
    "deck_dir", "common",     "bed",          "template_in", "out",
    "shape",    "vx_in_mps",  "vy_in_mps",    "w_in_radps",  "alpha_in_deg",
    "resuming", "restart_in", "resume_step0", "track_mode",  "checkpoint_prefix"};

}  // namespace

std::vector<DeckParam> read_deck_params(const std::string& path) {
  std::istringstream in(read_text(path));
  std::vector<DeckParam> params;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string kw, name, style, value;
    if (!(ls >> kw >> name >> style >> value) || kw != "variable" || style != "index") continue;
    DeckParam p;
    p.name = name;
    p.default_value = value;
    const auto hash = line.find('#');
    if (hash != std::string::npos) {
      p.comment = line.substr(hash + 1);
      p.comment.erase(0, p.comment.find_first_not_of(' '));
    }
    double v;
    // A default such as ${mu_gg} refers to another (numeric) parameter.
    p.numeric = parse_double(value, v) || value.rfind("${", 0) == 0;
    params.push_back(p);
  }
  return params;
}

Decks Decks::locate(const std::string& root) {
  const std::string r = root.empty() ? liggghts_inputs_dir().string() : root;
  Decks d;
  d.root = fs::absolute(r).lexically_normal().string();
  d.bed_deck = (fs::path(d.root) / "bed" / "in.bed").string();
  d.impact_dir = (fs::path(d.root) / "impact").string();
  d.common = (fs::path(d.root) / "common").string();
  for (const auto& f : {d.bed_deck, d.impact_dir + "/setup.in", d.impact_dir + "/check.in",
                        d.common + "/grain-defaults.in", d.common + "/block-defaults.in"})
    if (!fs::exists(f))
      throw std::runtime_error("LIGGGHTS decks not found: missing " + f +
                               " (give --decks DIR or set RICOCHET_LIGGGHTS_INPUTS)");
  d.bed_params = read_deck_params(d.common + "/grain-defaults.in");
  d.block_params = read_deck_params(d.common + "/block-defaults.in");
  for (auto& p : read_deck_params(d.impact_dir + "/setup.in"))
    if (!kWiring.count(p.name)) d.impact_params.push_back(p);
  return d;
}

std::string Decks::bed_decks_digest() const {
  std::vector<std::string> files = {bed_deck};
  // in.bed's own includes (bed/*.in: chunks.in) and the shared ones (common/*.in).
  for (const auto& dir : {fs::path(bed_deck).parent_path(), fs::path(common)})
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".in") files.push_back(e.path().string());
  std::sort(files.begin() + 1, files.end());
  // Comments, indentation and blank lines do not change a bed: hash what is left.
  std::uint64_t h = fnv1a("ricochet-bed-decks-2", kDemHashSeed);
  for (const auto& f : files) {
    h = fnv1a(fs::path(f).filename().string(), h);
    std::istringstream in(read_text(f));
    std::string line;
    while (std::getline(in, line)) {
      line = line.substr(0, line.find('#'));
      const auto b = line.find_first_not_of(" \t\r");
      if (b == std::string::npos) continue;
      line = line.substr(b, line.find_last_not_of(" \t\r") - b + 1);
      h = fnv1a(line + "\n", h);
    }
  }
  return fmt::format("{:016x}", h);
}

bool is_prime(std::int64_t n) {
  if (n < 2) return false;
  for (std::int64_t d = 2; d * d <= n; ++d)
    if (n % d == 0) return false;
  return true;
}

std::int64_t liggghts_seed(std::int64_t replica, std::int64_t offset) {
  const std::int64_t k = 1 + 2 * replica + offset;
  std::int64_t n = 10000, found = 0;
  while (found < k)
    if (is_prime(++n)) ++found;
  return n;
}

std::map<std::string, std::string> with_replica_seed(std::map<std::string, std::string> bed,
                                                     const std::optional<std::int64_t>& replica) {
  if (replica && !bed.count("seed")) bed["seed"] = std::to_string(liggghts_seed(*replica, 0));
  return bed;
}

void check_param(const Decks& decks, const std::string& section, const std::string& name,
                 const std::string& value, const std::string& file, std::size_t line) {
  const std::string field = section + "." + name;
  const auto& params = section_params(decks, section);
  const auto it = std::find_if(params.begin(), params.end(),
                               [&](const DeckParam& p) { return p.name == name; });
  if (it == params.end()) {
    std::string known;
    for (const auto& p : params) known += (known.empty() ? "" : ", ") + p.name;
    throw InputError(file, line, field, "unknown " + section + " parameter; known: " + known);
  }
  if (!it->numeric) {
    if (name == "mode" && value != "slab" && value != "box")
      throw InputError(file, line, field, "must be slab or box, not '" + value + "'");
    // epsd3 would also need a rollingStiffness property that the decks do not define.
    if (name == "rolling_model" && value != "epsd2" && value != "epsd" && value != "cdt")
      throw InputError(file, line, field, "must be one of epsd2, epsd, cdt, not '" + value + "'");
    return;
  }
  double v;
  if (!parse_double(value, v) || !std::isfinite(v))
    throw InputError(file, line, field, "expected a finite number, got '" + value + "'");
  auto ends_with = [&](const char* suffix) {
    const std::string s = suffix;
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  if (name == "seed" || name == "block_seed") {
    if (v != std::floor(v) || v <= 10000 || !is_prime(static_cast<std::int64_t>(v)))
      throw InputError(file, line, field,
                       "LIGGGHTS seeds must be primes above 10000 (or give a replica `seed` in "
                       "the design)");
    return;
  }
  const bool restitution = name.rfind("e_", 0) == 0;
  const bool friction = name.rfind("mu_", 0) == 0 || name.rfind("mur_", 0) == 0;
  const bool fraction = name == "f1" || name == "f2" || name == "f3";
  const bool can_be_negative =
      name == "vx_in_mps" || name == "vy_in_mps" || name == "w_in_radps" || name == "alpha_in_deg";
  // The active zone's half-length: 0 is its default, every grain (impact/zone.in).
  if (name == "active_zone_m") {
    if (v < 0) throw InputError(file, line, field, "must be >= 0 (0: every grain moves)");
    return;
  }
  // Steps between an impact's checkpoints (impact/checkpoint.in): 0 is none.
  if (name == "checkpoint_steps") {
    if (v < 0 || v != std::floor(v))
      throw InputError(file, line, field, "must be a whole number of steps >= 0 (0: none)");
    return;
  }
  if (restitution && !(v > 0 && v <= 1))
    throw InputError(file, line, field, "a restitution coefficient must be in (0, 1]");
  if ((friction || fraction) && v < 0) throw InputError(file, line, field, "must be >= 0");
  if (!restitution && !friction && !fraction && !can_be_negative && !(v > 0))
    throw InputError(file, line, field, "must be > 0");
  if ((name == "nu_grain" || name == "nu_block") && !(v < 0.5))
    throw InputError(file, line, field, "Poisson's ratio must be < 0.5");
  if ((name == "dt_frac" || name == "x_impact_frac" || name == "phi_pour") && !(v < 1))
    throw InputError(file, line, field, "must be < 1");
  if ((ends_with("_every") || ends_with("_steps")) && v != std::floor(v))
    throw InputError(file, line, field, "must be a whole number of steps");
}

void apply_set_option(const Decks& decks, const std::string& assignment, Overrides& o) {
  const auto eq = assignment.find('=');
  const auto dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq)
    throw InputError(
        "<command line>", 0, "--set",
        "expected SECTION.NAME=VALUE (SECTION bed, block or run), got '" + assignment + "'");
  const std::string section = assignment.substr(0, dot);
  const std::string name = assignment.substr(dot + 1, eq - dot - 1);
  const std::string value = assignment.substr(eq + 1);
  if (section != "bed" && section != "block" && section != "run")
    throw InputError("<command line>", 0, "--set",
                     "unknown section '" + section + "'; use bed, block or run");
  check_param(decks, section, name, value, "<command line>", 0);
  (section == "bed" ? o.bed : section == "block" ? o.block : o.run)[name] = value;
}

namespace {

// A run.* parameter's override or deck default; nullopt when the deck does not have it.
std::optional<double> run_param_if(const Decks& decks,
                                   const std::map<std::string, std::string>& run,
                                   const std::string& name) {
  if (const auto it = run.find(name); it != run.end()) return std::stod(it->second);
  for (const auto& p : decks.impact_params)
    if (p.name == name) return std::stod(p.default_value);
  return std::nullopt;
}

}  // namespace

double run_param(const Decks& decks, const std::map<std::string, std::string>& run,
                 const std::string& name) {
  if (const auto v = run_param_if(decks, run, name)) return *v;
  throw std::logic_error("impact deck has no parameter " + name);
}

long checkpoint_steps_of(const Decks& decks, const std::map<std::string, std::string>& run) {
  return static_cast<long>(run_param_if(decks, run, "checkpoint_steps").value_or(0));
}

std::vector<std::pair<std::string, std::string>> effective_bed(
    const Decks& decks, const std::map<std::string, std::string>& bed) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& p : decks.bed_params) {
    const auto it = bed.find(p.name);
    std::string value = it == bed.end() ? p.default_value : it->second;
    // Canonical numbers, so that 1e8 and 100000000 name the same bed.
    double v;
    if (p.numeric && parse_double(value, v)) value = shortest_number(v);
    out.emplace_back(p.name, value);
  }
  return out;
}

double bed_param(const Decks& decks, const std::map<std::string, std::string>& bed,
                 const std::string& name) {
  for (const auto& [n, value] : effective_bed(decks, bed))
    if (n == name) return std::stod(value);
  throw std::logic_error("bed deck has no parameter " + name);
}

std::string bed_key(const Decks& decks, const std::map<std::string, std::string>& bed) {
  std::string text = decks.bed_decks_digest();
  for (const auto& [name, value] : effective_bed(decks, bed)) text += "\n" + name + "=" + value;
  return fmt::format("{:016x}", fnv1a(text, kDemHashSeed));
}

}  // namespace ricochet::dem
