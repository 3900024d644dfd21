#include "effects/model.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "effects/coefficient_law.hpp"

namespace ricochet {

Model Model::paper(const EffectRegistry& registry) {
  return from_names({"normal", "tangential", "rolling"}, registry);
}

Model Model::from_names(const std::vector<std::string>& names, const EffectRegistry& registry) {
  Model m;
  for (const auto& n : names) m.add(registry.get(n));
  m.finish();
  return m;
}

void Model::add(const Effect& effect) {
  for (const Effect* e : effects_)
    if (e->name() == effect.name())
      throw std::invalid_argument("effect '" + std::string(effect.name()) +
                                  "' appears twice in the model");
  for (const auto& p : effect.parameters())
    for (const auto& q : specs_)
      if (p.name == q.name)
        throw std::invalid_argument("parameter '" + std::string(p.name) + "' of effect '" +
                                    std::string(effect.name()) +
                                    "' is already declared by another effect of the model");
  effects_.push_back(&effect);
  for (const auto& p : effect.parameters()) specs_.push_back(p);
}

void Model::finish() {
  // Stage order; stable so that the user's order holds within a stage.
  std::stable_sort(effects_.begin(), effects_.end(), [](const Effect* a, const Effect* b) {
    return static_cast<int>(a->stage()) < static_cast<int>(b->stage());
  });
  if (std::none_of(effects_.begin(), effects_.end(),
                   [](const Effect* e) { return e->stage() == Stage::kNormal; }))
    throw std::invalid_argument("a model needs a normal-force effect such as 'normal'");
  specs_.clear();
  offsets_.clear();
  for (const Effect* e : effects_) {
    offsets_.push_back(specs_.size());
    for (const auto& p : e->parameters()) specs_.push_back(p);
  }
  values_.clear();
  lower_.clear();
  upper_.clear();
  calibrated_.clear();
  held_.clear();
  for (const auto& p : specs_) {
    values_.push_back(p.nominal);
    lower_.push_back(p.lower);
    upper_.push_back(p.upper);
    calibrated_.push_back(p.calibrated);
    held_.push_back(false);
  }
}

Model Model::with_effect(std::string_view name, bool at_neutral,
                         const EffectRegistry& registry) const {
  Model m;
  for (const Effect* e : effects_) m.add(*e);
  m.add(registry.get(name));
  m.finish();
  // Carry over values, bounds and calibration flags of the existing parameters.
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const std::size_t j = m.index(specs_[i].name);
    m.values_[j] = values_[i];
    m.lower_[j] = lower_[i];
    m.upper_[j] = upper_[i];
    m.calibrated_[j] = calibrated_[i];
    m.held_[j] = held_[i];
  }
  if (at_neutral)
    for (const auto& p : registry.get(name).parameters())
      if (!std::isnan(p.neutral)) m.values_[m.index(p.name)] = p.neutral;
  return m;
}

std::vector<std::string> Model::effect_names() const {
  std::vector<std::string> out;
  for (const Effect* e : effects_) out.emplace_back(e->name());
  return out;
}

bool Model::has_effect(std::string_view name) const {
  return std::any_of(effects_.begin(), effects_.end(),
                     [&](const Effect* e) { return e->name() == name; });
}

std::size_t Model::index(std::string_view name) const {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (specs_[i].name == name) return i;
  std::string known;
  for (const auto& p : specs_) known += (known.empty() ? "" : ", ") + std::string(p.name);
  throw std::invalid_argument("unknown parameter '" + std::string(name) +
                              "'; parameters of this model: " + known);
}

std::vector<std::string> Model::parameter_names() const {
  std::vector<std::string> out;
  for (const auto& p : specs_) out.emplace_back(p.name);
  return out;
}

namespace {
std::string bounds_message(const ParameterSpec& p, double v, double lo, double hi) {
  std::ostringstream s;
  s << p.name << " = " << v << " is outside [" << lo << ", " << hi << "] " << p.unit;
  return s.str();
}
}  // namespace

void Model::set(std::string_view name, double value) {
  const std::size_t i = index(name);
  const auto& p = specs_[i];
  if (!(value >= p.lower && value <= p.upper))
    throw std::out_of_range(bounds_message(p, value, p.lower, p.upper));
  values_[i] = value;
}

void Model::set_values(const std::vector<double>& values) {
  if (values.size() != values_.size())
    throw std::invalid_argument("parameter vector has " + std::to_string(values.size()) +
                                " values, the model " + std::to_string(values_.size()));
  check(values);
  values_ = values;
}

void Model::set_from_string(const std::string& assignment, const std::string& option) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("<command line>", 0, option, "expected NAME=VALUE, got '" + assignment + "'");
  const std::string name = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  double v = 0;
  try {
    std::size_t used = 0;
    v = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw InputError("<command line>", 0, option,
                     "value of '" + name + "' is not a number: '" + text + "'");
  }
  try {
    set(name, v);
  } catch (const std::exception& e) {
    throw InputError("<command line>", 0, option, e.what());
  }
}

void Model::set_bounds(std::string_view name, double lower, double upper) {
  const std::size_t i = index(name);
  const auto& p = specs_[i];
  if (!(lower <= upper) || lower < p.lower || upper > p.upper)
    throw std::out_of_range("bounds [" + std::to_string(lower) + ", " + std::to_string(upper) +
                            "] of '" + std::string(name) + "' must lie within [" +
                            std::to_string(p.lower) + ", " + std::to_string(p.upper) + "]");
  lower_[i] = lower;
  upper_[i] = upper;
}

void Model::set_calibrated(std::string_view name, bool on) {
  const std::size_t i = index(name);
  if (on && held_[i])
    throw std::invalid_argument("'" + std::string(name) + "' is held: it cannot be calibrated too");
  calibrated_[i] = on;
}

void Model::set_held(std::string_view name, bool on) {
  const std::size_t i = index(name);
  held_[i] = on;
  if (on) calibrated_[i] = false;
}

std::vector<std::size_t> Model::calibrated_indices() const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < calibrated_.size(); ++i)
    if (calibrated_[i]) out.push_back(i);
  return out;
}

void Model::check(const std::vector<double>& values) const {
  for (std::size_t i = 0; i < specs_.size(); ++i)
    if (!(values[i] >= specs_[i].lower && values[i] <= specs_[i].upper))
      throw std::out_of_range(
          bounds_message(specs_[i], values[i], specs_[i].lower, specs_[i].upper));
}

nlohmann::json Model::to_json() const {
  nlohmann::json j;
  j["effects"] = effect_names();
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    const std::string n(specs_[i].name);
    j["parameters"][n] = values_[i];
    j["units"][n] = std::string(specs_[i].unit);
    j["bounds"][n] = {lower_[i], upper_[i]};
  }
  j["calibrate"] = names_of(calibrated_);
  if (const auto held = names_of(held_); !held.empty()) j["hold"] = held;
  return j;
}

std::vector<std::string> Model::names_of(const std::vector<bool>& flags) const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < flags.size(); ++i)
    if (flags[i]) out.emplace_back(specs_[i].name);
  return out;
}

namespace {
// A double as TOML text that reads back to the same bits: the shortest form at 17 digits, with
// "-0.0" for negative zero (std::ostream writes "-0", which TOML reads as the integer 0).
struct TomlNumber {
  double v;
};
std::ostream& operator<<(std::ostream& s, TomlNumber n) {
  if (n.v == 0 && std::signbit(n.v)) return s << "-0.0";
  return s << n.v;
}
}  // namespace

std::string Model::to_toml() const {
  std::ostringstream s;
  s.precision(17);
  // Generated coefficient laws are written as [[law]] tables. Read back, those land after the
  // coefficient-stage effects named in `effects`; a law that precedes a hand-written coefficient
  // effect therefore keeps its name in `effects`, so that the order of the factors, and with it
  // every bit of a result, survives the round trip.
  std::size_t first_table = 0;  // effects before this index are written by name
  for (std::size_t e = 0; e < effects_.size(); ++e)
    if (effects_[e]->stage() == Stage::kCoefficient &&
        !effects::parse_coefficient_law_name(effects_[e]->name()))
      first_table = e + 1;
  std::vector<std::string> law_text(effects_.size());
  for (std::size_t e = 0; e < effects_.size(); ++e) {
    if (!effects::parse_coefficient_law_name(effects_[e]->name())) continue;
    const std::vector<double> v(
        values_.begin() + static_cast<std::ptrdiff_t>(offsets_[e]),
        values_.begin() +
            static_cast<std::ptrdiff_t>(offsets_[e] + effects_[e]->parameters().size()));
    law_text[e] = effects_[e]->law(v);
    if (e < first_table) s << "# " << effects_[e]->name() << ": " << law_text[e] << "\n";
  }
  s << "effects = [";
  bool first = true;
  for (std::size_t e = 0; e < effects_.size(); ++e) {
    if (e >= first_table && effects::parse_coefficient_law_name(effects_[e]->name())) continue;
    s << (first ? "" : ", ") << '"' << effects_[e]->name() << '"';
    first = false;
  }
  s << "]\n";
  const auto write_names = [&s](const char* key, const std::vector<std::string>& names) {
    s << key << " = [";
    for (std::size_t i = 0; i < names.size(); ++i) s << (i ? ", " : "") << '"' << names[i] << '"';
    s << "]\n";
  };
  write_names("calibrate", names_of(calibrated_));
  // Only when something is held, so that every model file written before `hold` reads back
  // to the same text.
  if (const auto held = names_of(held_); !held.empty()) write_names("hold", held);
  for (std::size_t e = first_table; e < effects_.size(); ++e) {
    const auto law = effects::parse_coefficient_law_name(effects_[e]->name());
    if (!law) continue;
    s << "\n# " << law_text[e] << "\n[[law]]\ncoefficient = \"" << law->coefficient
      << "\"\nvariable = \"" << law->variable << "\"\nform = \"" << law->form << "\"\n";
  }
  s << "\n[parameters]\n";
  for (std::size_t i = 0; i < specs_.size(); ++i)
    s << specs_[i].name << " = " << TomlNumber{values_[i]} << "  # " << specs_[i].unit << "\n";
  s << "\n[bounds]\n";
  for (std::size_t i = 0; i < specs_.size(); ++i)
    s << specs_[i].name << " = [" << TomlNumber{lower_[i]} << ", " << TomlNumber{upper_[i]}
      << "]\n";
  return s.str();
}

namespace {

std::size_t line_of(const toml::node& node) {
  return static_cast<std::size_t>(node.source().begin.line);
}

double number_or_throw(const toml::node& node, const std::string& file, const std::string& key) {
  if (auto v = node.value<double>()) return *v;
  throw InputError(file, line_of(node), key, "expected a number");
}

}  // namespace

Model Model::from_toml_string(const std::string& text, const std::string& name,
                              const EffectRegistry& registry) {
  toml::table table;
  try {
    table = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(name, static_cast<std::size_t>(e.source().begin.line), "",
                     std::string(e.description()));
  }
  for (const auto& [key, node] : table) {
    const std::string k(key.str());
    if (k != "effects" && k != "calibrate" && k != "hold" && k != "parameters" && k != "bounds" &&
        k != "law")
      throw InputError(name, line_of(node), k,
                       "unknown key; a model file has effects, calibrate, hold, [parameters], "
                       "[bounds], [[law]]");
  }
  // A present key of the wrong kind is an error, not an absent key (found by
  // fuzz/fuzz_model_toml: `calibrate = 0` was ignored).
  const std::pair<const char*, bool> kinds[] = {{"effects", false},
                                                {"calibrate", false},
                                                {"hold", false},
                                                {"parameters", true},
                                                {"bounds", true}};
  for (const auto& [key, is_table] : kinds) {
    const toml::node* n = table.get(key);
    if (n && (is_table ? !n->is_table() : !n->is_array()))
      throw InputError(name, line_of(*n), key,
                       is_table ? "expected a table ([" + std::string(key) + "])"
                                : "expected a list of names in [\"...\"]");
  }
  const toml::array* effects = table["effects"].as_array();
  if (!effects)
    throw InputError(name, 1, "effects",
                     "missing list of effects, e.g. effects = [\"normal\", \"tangential\", "
                     "\"rolling\"]");
  std::vector<std::string> names;
  for (const auto& e : *effects) {
    auto s = e.value<std::string>();
    if (!s) throw InputError(name, line_of(e), "effects", "effect names must be strings");
    if (!registry.contains(*s)) {
      try {
        registry.get(*s);
      } catch (const std::exception& ex) {
        throw InputError(name, line_of(e), "effects", ex.what());
      }
    }
    names.push_back(*s);
  }
  // [[law]] tables: generated coefficient laws given by their configuration.
  if (const toml::node* laws = table.get("law")) {
    const toml::array* arr = laws->as_array();
    if (!arr || !arr->is_array_of_tables())
      throw InputError(name, line_of(*laws), "law",
                       "expected [[law]] tables with coefficient, variable and form; " +
                           effects::coefficient_law_family_text());
    const char* keys[3] = {"coefficient", "variable", "form"};
    const std::span<const std::string_view> accepted[3] = {
        effects::law_coefficients(), effects::law_variables(), effects::law_forms()};
    const auto accepted_text = [&](int k) {
      std::string out = "; accepted: ";
      for (std::size_t i = 0; i < accepted[k].size(); ++i)
        out += (i ? ", " : "") + std::string(accepted[k][i]);
      return out;
    };
    for (const auto& entry : *arr) {
      const toml::table& t = *entry.as_table();
      for (const auto& [key, node] : t) {
        const std::string kk(key.str());
        if (kk != keys[0] && kk != keys[1] && kk != keys[2])
          throw InputError(name, line_of(node), "law." + kk,
                           "unknown key; a [[law]] has coefficient, variable and form");
      }
      std::string field[3];
      for (int k = 0; k < 3; ++k) {
        const std::string key = std::string("law.") + keys[k];
        const toml::node* node = t.get(keys[k]);
        if (!node) throw InputError(name, line_of(entry), key, "missing" + accepted_text(k));
        auto v = node->value<std::string>();
        if (!v) throw InputError(name, line_of(*node), key, "expected a string" + accepted_text(k));
        if (std::find(accepted[k].begin(), accepted[k].end(), *v) == accepted[k].end())
          throw InputError(name, line_of(*node), key,
                           "unknown " + std::string(keys[k]) + " '" + *v + "'" + accepted_text(k));
        field[k] = *v;
      }
      const std::string law = effects::coefficient_law_name(field[0], field[1], field[2]);
      if (std::find(names.begin(), names.end(), law) != names.end())
        throw InputError(name, line_of(entry), "law", "'" + law + "' is already in the model");
      names.push_back(law);
    }
  }
  Model m;
  try {
    m = from_names(names, registry);
  } catch (const std::exception& ex) {
    throw InputError(name, line_of(*effects), "effects", ex.what());
  }
  if (const toml::table* params = table["parameters"].as_table()) {
    for (const auto& [key, node] : *params) {
      const std::string k(key.str());
      try {
        m.set(k, number_or_throw(node, name, "parameters." + k));
      } catch (const InputError&) {
        throw;
      } catch (const std::exception& ex) {
        throw InputError(name, line_of(node), "parameters." + k, ex.what());
      }
    }
  }
  if (const toml::table* bounds = table["bounds"].as_table()) {
    for (const auto& [key, node] : *bounds) {
      const std::string k(key.str());
      const toml::array* pair = node.as_array();
      if (!pair || pair->size() != 2)
        throw InputError(name, line_of(node), "bounds." + k, "expected [lower, upper]");
      try {
        m.set_bounds(k, number_or_throw(*pair->get(0), name, "bounds." + k),
                     number_or_throw(*pair->get(1), name, "bounds." + k));
      } catch (const InputError&) {
        throw;
      } catch (const std::exception& ex) {
        throw InputError(name, line_of(node), "bounds." + k, ex.what());
      }
    }
  }
  if (const toml::array* cal = table["calibrate"].as_array()) {
    for (std::size_t i = 0; i < m.parameter_count(); ++i) m.calibrated_[i] = false;
    for (const auto& e : *cal) {
      auto s = e.value<std::string>();
      if (!s) throw InputError(name, line_of(e), "calibrate", "parameter names must be strings");
      try {
        m.set_calibrated(*s, true);
      } catch (const std::exception& ex) {
        throw InputError(name, line_of(e), "calibrate", ex.what());
      }
    }
  }
  if (const toml::array* hold = table["hold"].as_array()) {
    for (const auto& e : *hold) {
      auto s = e.value<std::string>();
      if (!s) throw InputError(name, line_of(e), "hold", "parameter names must be strings");
      try {
        if (m.calibrated(m.index(*s)) && table["calibrate"].as_array())
          throw std::invalid_argument("'" + *s + "' is both in calibrate and held");
        m.set_held(*s, true);
      } catch (const std::exception& ex) {
        throw InputError(name, line_of(e), "hold", ex.what());
      }
    }
  }
  return m;
}

Model Model::from_toml_file(const std::string& path, const EffectRegistry& registry) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot open model file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return from_toml_string(buffer.str(), path, registry);
}

}  // namespace ricochet
