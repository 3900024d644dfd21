// The impact-set schema: column table, units, invariants, features and filters.
// The CSV form lives in impact_csv.cpp, the HDF5 form in impact_h5.cpp. This file must stay free
// of HDF5 so that the fuzz target can compile it alone.
#include "impact/impact_set.hpp"
#include "common/nan.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "impact/schema_detail.hpp"

namespace ricochet {
namespace impact_detail {
namespace {

bool has_control_char(std::string_view s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
}

// Text cells: present text is never empty (an empty optional cell means "absent") and never holds
// control characters, so that every writer can emit it on one line and read it back unchanged.
void check_text(const std::string& value, const char* field, const std::string& file,
                std::size_t line) {
  if (value.empty()) throw InputError(file, line, field, "empty text");
  if (has_control_char(value))
    throw InputError(file, line, field, "contains a control character (tab, newline, ...)");
}

void check_finite(double v, const char* field, const std::string& file, std::size_t line) {
  if (!std::isfinite(v)) throw InputError(file, line, field, "value is not finite (NaN or inf)");
}

void check_non_negative(double v, const char* field, const char* unit, const std::string& file,
                        std::size_t line) {
  check_finite(v, field, file, line);
  if (v < 0)
    throw InputError(file, line, field,
                     "value " + shortest_number(v) + " " + unit + " is negative; it must be >= 0");
}

}  // namespace

const std::vector<ColumnSpec>& schema_columns() {
  static const std::vector<ColumnSpec> columns = {
      {Col::kId, "id", Dim::kText, true},
      {Col::kShape, "shape", Dim::kText, true},
      {Col::kVinX, "vin_x", Dim::kVelocity, true},
      {Col::kVinY, "vin_y", Dim::kVelocity, true},
      {Col::kWin, "win", Dim::kAngularVelocity, true},
      {Col::kVoutX, "vout_x", Dim::kVelocity, true},
      {Col::kVoutY, "vout_y", Dim::kVelocity, true},
      {Col::kWout, "wout", Dim::kAngularVelocity, true},
      {Col::kAlphaIn, "alpha_in", Dim::kAngle, false},
      {Col::kPenetration, "penetration", Dim::kLength, false},
      {Col::kContactDuration, "contact_duration", Dim::kTime, false},
      {Col::kOperator, "operator", Dim::kText, false},
      {Col::kReplicate, "replicate", Dim::kText, false},
      {Col::kWeight, "weight", Dim::kDimensionless, false},
      {Col::kSigmaVinX, "sigma_vin_x", Dim::kVelocity, false},
      {Col::kSigmaVinY, "sigma_vin_y", Dim::kVelocity, false},
      {Col::kSigmaVinW, "sigma_vin_w", Dim::kAngularVelocity, false},
      {Col::kSigmaVoutX, "sigma_vout_x", Dim::kVelocity, false},
      {Col::kSigmaVoutY, "sigma_vout_y", Dim::kVelocity, false},
      {Col::kSigmaVoutW, "sigma_vout_w", Dim::kAngularVelocity, false},
  };
  return columns;
}

const ColumnSpec* find_column(std::string_view name) {
  for (const auto& c : schema_columns())
    if (name == c.name) return &c;
  return nullptr;
}

bool is_reserved_name(std::string_view name) {
  return find_column(name) != nullptr || name == "speed_in";
}

bool is_valid_column_name(std::string_view name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

std::optional<double> get_numeric(const Impact& m, Col col) {
  switch (col) {
    case Col::kVinX:
      return m.vin[kVx];
    case Col::kVinY:
      return m.vin[kVy];
    case Col::kWin:
      return m.vin[kW];
    case Col::kVoutX:
      return m.vout[kVx];
    case Col::kVoutY:
      return m.vout[kVy];
    case Col::kWout:
      return m.vout[kW];
    case Col::kAlphaIn:
      return m.alpha_in;
    case Col::kPenetration:
      return m.penetration;
    case Col::kContactDuration:
      return m.contact_duration;
    case Col::kWeight:
      return m.weight;
    case Col::kSigmaVinX:
      return m.sigma_vin ? std::optional((*m.sigma_vin)[kVx]) : std::nullopt;
    case Col::kSigmaVinY:
      return m.sigma_vin ? std::optional((*m.sigma_vin)[kVy]) : std::nullopt;
    case Col::kSigmaVinW:
      return m.sigma_vin ? std::optional((*m.sigma_vin)[kW]) : std::nullopt;
    case Col::kSigmaVoutX:
      return m.sigma_vout ? std::optional((*m.sigma_vout)[kVx]) : std::nullopt;
    case Col::kSigmaVoutY:
      return m.sigma_vout ? std::optional((*m.sigma_vout)[kVy]) : std::nullopt;
    case Col::kSigmaVoutW:
      return m.sigma_vout ? std::optional((*m.sigma_vout)[kW]) : std::nullopt;
    case Col::kId:
    case Col::kShape:
    case Col::kOperator:
    case Col::kReplicate:
      break;
  }
  return std::nullopt;
}

void set_numeric(Impact& m, Col col, double v) {
  auto sigma = [&](std::optional<Vel3>& s, Component c) {
    if (!s) s = Vel3{0.0, 0.0, 0.0};
    (*s)[c] = v;
  };
  switch (col) {
    case Col::kVinX:
      m.vin[kVx] = v;
      break;
    case Col::kVinY:
      m.vin[kVy] = v;
      break;
    case Col::kWin:
      m.vin[kW] = v;
      break;
    case Col::kVoutX:
      m.vout[kVx] = v;
      break;
    case Col::kVoutY:
      m.vout[kVy] = v;
      break;
    case Col::kWout:
      m.vout[kW] = v;
      break;
    case Col::kAlphaIn:
      m.alpha_in = v;
      break;
    case Col::kPenetration:
      m.penetration = v;
      break;
    case Col::kContactDuration:
      m.contact_duration = v;
      break;
    case Col::kWeight:
      m.weight = v;
      break;
    case Col::kSigmaVinX:
      sigma(m.sigma_vin, kVx);
      break;
    case Col::kSigmaVinY:
      sigma(m.sigma_vin, kVy);
      break;
    case Col::kSigmaVinW:
      sigma(m.sigma_vin, kW);
      break;
    case Col::kSigmaVoutX:
      sigma(m.sigma_vout, kVx);
      break;
    case Col::kSigmaVoutY:
      sigma(m.sigma_vout, kVy);
      break;
    case Col::kSigmaVoutW:
      sigma(m.sigma_vout, kW);
      break;
    case Col::kId:
    case Col::kShape:
    case Col::kOperator:
    case Col::kReplicate:
      break;
  }
}

bool has_column(const Impact& m, Col col) {
  switch (col) {
    case Col::kId:
    case Col::kShape:
      return true;
    case Col::kOperator:
      return m.op.has_value();
    case Col::kReplicate:
      return m.replicate.has_value();
    default:
      return get_numeric(m, col).has_value();
  }
}

void check_impact(const Impact& m, std::size_t n_extra, const std::string& file, std::size_t line,
                  bool incident_only) {
  check_text(m.id, "id", file, line);
  check_text(m.shape, "shape", file, line);
  // An incident state (read_incident_states: a plan of throws) has no reflected velocity yet.
  const bool no_vout =
      incident_only && std::isnan(m.vout[kVx]) && std::isnan(m.vout[kVy]) && std::isnan(m.vout[kW]);
  for (const auto& spec : schema_columns()) {
    if (spec.dim == Dim::kText) continue;
    if (no_vout && (spec.col == Col::kVoutX || spec.col == Col::kVoutY || spec.col == Col::kWout))
      continue;
    const auto v = get_numeric(m, spec.col);
    if (v) check_finite(*v, spec.name, file, line);
  }
  // Frame of paper Fig. 1 (y up): the block falls onto the ground and leaves it upwards.
  if (m.vin[kVy] >= 0)
    throw InputError(file, line, "vin_y",
                     "incident vertical velocity " + shortest_number(m.vin[kVy]) +
                         " m/s must be negative (y is up: the block falls onto the ground)");
  if (!no_vout && m.vout[kVy] <= 0)
    throw InputError(file, line, "vout_y",
                     "reflected vertical velocity " + shortest_number(m.vout[kVy]) +
                         " m/s must be positive (y is up: the block leaves the ground)");
  if (m.penetration) check_non_negative(*m.penetration, "penetration", "m", file, line);
  if (m.contact_duration)
    check_non_negative(*m.contact_duration, "contact_duration", "s", file, line);
  if (m.weight) check_non_negative(*m.weight, "weight", "-", file, line);
  if (m.op) check_text(*m.op, "operator", file, line);
  if (m.replicate) check_text(*m.replicate, "replicate", file, line);
  const char* sigma_names[2][3] = {{"sigma_vin_x", "sigma_vin_y", "sigma_vin_w"},
                                   {"sigma_vout_x", "sigma_vout_y", "sigma_vout_w"}};
  const std::optional<Vel3>* sigmas[2] = {&m.sigma_vin, &m.sigma_vout};
  for (int s = 0; s < 2; ++s) {
    if (!*sigmas[s]) continue;
    for (int c = 0; c < 3; ++c)
      check_non_negative((**sigmas[s])[c], sigma_names[s][c], c == kW ? "rad/s" : "m/s", file,
                         line);
  }
  if (m.extra.size() != n_extra)
    throw InputError(file, line, "extra",
                     "impact '" + m.id + "' has " + std::to_string(m.extra.size()) +
                         " extra values but the set declares " + std::to_string(n_extra));
  for (double v : m.extra)
    if (std::isinf(v)) throw InputError(file, line, "extra", "extra value is infinite");
}

void check_extras_declaration(const ImpactSet& set, const std::string& file, std::size_t line) {
  if (set.extra_names.size() != set.extra_units.size())
    throw InputError(file, line, "extra_units",
                     "extra_names and extra_units have different lengths");
  std::unordered_set<std::string> seen;
  for (std::size_t i = 0; i < set.extra_names.size(); ++i) {
    const auto& name = set.extra_names[i];
    if (!is_valid_column_name(name))
      throw InputError(file, line, name, "column names may only use letters, digits and '_'");
    if (is_reserved_name(name))
      throw InputError(file, line, name, "name is reserved by the schema");
    if (!seen.insert(name).second) throw InputError(file, line, name, "duplicate column");
    const Unit* u = find_unit(set.extra_units[i]);
    if (!u || u->to_si != 1.0)
      throw InputError(file, line, name,
                       "extra unit '" + set.extra_units[i] +
                           "' is not an SI unit of the schema (m/s, rad/s, m, s, rad, -)");
  }
}

bool parse_number(std::string_view text, double& value) {
  // from_chars rejects a leading '+', which spreadsheets sometimes write; accept "+1.5" only.
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (text.empty() || text.front() == '-' || text.front() == '+') return false;
  }
  if (text.empty()) return false;
  const auto res = std::from_chars(text.data(), text.data() + text.size(), value);
  return res.ec == std::errc() && res.ptr == text.data() + text.size();
}

void RowAssembler::store(Impact& m, const ColumnSpec* spec, std::size_t extra_index,
                         double value_si) {
  if (!spec) {
    m.extra[extra_index] = value_si;
    return;
  }
  set_numeric(m, spec->col, value_si);
  // schema_columns() lists the six sigma columns consecutively from kSigmaVinX.
  const int k = static_cast<int>(spec->col) - static_cast<int>(Col::kSigmaVinX);
  if (k >= 0 && k < 6) sigma_given_[k / 3][k % 3] = true;
}

void RowAssembler::finish(Impact&& m, ImpactSet& set, std::size_t line) {
  for (int s = 0; s < 2; ++s) {
    const bool any = sigma_given_[s][0] || sigma_given_[s][1] || sigma_given_[s][2];
    for (int k = 0; k < 3 && any; ++k)
      if (!sigma_given_[s][k])
        throw InputError(
            file_, line, schema_columns()[static_cast<int>(Col::kSigmaVinX) + 3 * s + k].name,
            std::string(missing_) + ": give all three components of the uncertainty or none");
  }
  sigma_given_ = {};
  check_impact(m, set.extra_names.size(), file_, line, incident_only_);
  const auto [it, inserted] = id_line_.emplace(m.id, line);
  if (!inserted)
    throw InputError(
        file_, line, "id",
        "duplicate id '" + m.id + "' (first on " + place_ + " " + std::to_string(it->second) + ")");
  set.impacts.push_back(std::move(m));
}

}  // namespace impact_detail

using namespace impact_detail;

namespace {

const char* const kDerivedFeatures[] = {
    "vin_x",    "vin_y",    "win",         "vout_x",           "vout_y", "wout",
    "speed_in", "alpha_in", "penetration", "contact_duration", "weight"};

std::string known_feature_list(const ImpactSet& set) {
  std::string out;
  for (const char* n : kDerivedFeatures) out += std::string(out.empty() ? "" : ", ") + n;
  for (const auto& n : set.extra_names) out += ", " + n;
  return out;
}

}  // namespace

std::vector<double> ImpactSet::feature(const std::string& name) const {
  std::vector<double> out;
  out.reserve(impacts.size());
  if (name == "speed_in") {
    for (const auto& m : impacts) out.push_back(std::hypot(m.vin[kVx], m.vin[kVy]));
    return out;
  }
  if (const ColumnSpec* spec = find_column(name);
      spec && spec->dim != Dim::kText && name.rfind("sigma_", 0) != 0) {
    for (const auto& m : impacts) out.push_back(get_numeric(m, spec->col).value_or(kNaN));
    return out;
  }
  const auto it = std::find(extra_names.begin(), extra_names.end(), name);
  if (it == extra_names.end())
    throw std::invalid_argument("unknown feature '" + name +
                                "'; known: " + known_feature_list(*this));
  const auto k = static_cast<std::size_t>(it - extra_names.begin());
  for (const auto& m : impacts) out.push_back(k < m.extra.size() ? m.extra[k] : kNaN);
  return out;
}

std::vector<std::string> ImpactSet::feature_names() const {
  std::vector<std::string> names;
  auto any_value = [&](const std::string& n) {
    const auto v = feature(n);
    return std::any_of(v.begin(), v.end(), [](double x) { return !std::isnan(x); });
  };
  for (const char* n : kDerivedFeatures)
    if (any_value(n)) names.emplace_back(n);
  for (const auto& n : extra_names)
    if (any_value(n)) names.push_back(n);
  return names;
}

ImpactSet ImpactSet::with_shape(const std::string& shape) const {
  ImpactSet out = *this;
  if (shape.empty()) return out;
  out.impacts.clear();
  for (const auto& m : impacts)
    if (m.shape == shape) out.impacts.push_back(m);
  return out;
}

void validate(const ImpactSet& set) {
  check_extras_declaration(set, set.source, 0);
  std::unordered_map<std::string, std::size_t> first_row;
  for (std::size_t i = 0; i < set.impacts.size(); ++i) {
    const Impact& m = set.impacts[i];
    check_impact(m, set.extra_names.size(), set.source, i + 1);
    const auto [it, inserted] = first_row.emplace(m.id, i + 1);
    if (!inserted)
      throw InputError(
          set.source, i + 1, "id",
          "duplicate id '" + m.id + "' (first at row " + std::to_string(it->second) + ")");
  }
}

// ---------------------------------------------------------------------------------------------
// Filters ("vin_x<3.5 && shape==triangle").

namespace {

enum class Op { kLt, kLe, kGt, kGe, kEq, kNe, kPrefix };

struct Term {
  std::string text;     // the term as written, for messages
  std::string feature;  // feature name, or id/shape/operator
  Op op = Op::kEq;
  bool textual = false;
  std::string text_value;
  double value = 0;
  std::vector<double> values;  // numeric feature over the set
};

[[noreturn]] void bad_term(const std::string& option, const std::string& term,
                           const std::string& message) {
  throw InputError(option, 0, term, message);
}

// Splits on "&&" and on the word "and" (case-insensitive, surrounded by whitespace).
std::vector<std::string> split_terms(const std::string& where) {
  std::vector<std::string> pieces;
  std::string current;
  auto is_space = [](char c) { return c == ' ' || c == '\t'; };
  auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c + 32) : c; };
  for (std::size_t i = 0; i < where.size();) {
    if (where.compare(i, 2, "&&") == 0) {
      pieces.push_back(current);
      current.clear();
      i += 2;
      continue;
    }
    if (is_space(where[i]) && i + 4 < where.size() && lower(where[i + 1]) == 'a' &&
        lower(where[i + 2]) == 'n' && lower(where[i + 3]) == 'd' && is_space(where[i + 4])) {
      pieces.push_back(current);
      current.clear();
      i += 5;
      continue;
    }
    current += where[i++];
  }
  pieces.push_back(current);
  return pieces;
}

Term parse_term(const std::string& raw, const std::string& where, const ImpactSet& set,
                const std::string& option) {
  Term t;
  t.text = std::string(trim(raw));
  if (t.text.empty()) bad_term(option, where, "empty condition (a dangling '&&' or 'and'?)");
  const auto pos = t.text.find_first_of("<>=!^");
  if (pos == std::string::npos)
    bad_term(option, t.text,
             "no comparison operator; write FEATURE OP VALUE with OP in < <= > >= == != ^=");
  const std::string_view rest = std::string_view(t.text).substr(pos);
  std::size_t op_len = 2;
  if (rest.starts_with("<=")) {
    t.op = Op::kLe;
  } else if (rest.starts_with(">=")) {
    t.op = Op::kGe;
  } else if (rest.starts_with("==")) {
    t.op = Op::kEq;
  } else if (rest.starts_with("!=")) {
    t.op = Op::kNe;
  } else if (rest.starts_with("^=")) {
    t.op = Op::kPrefix;
  } else if (rest.starts_with("<")) {
    t.op = Op::kLt;
    op_len = 1;
  } else if (rest.starts_with(">")) {
    t.op = Op::kGt;
    op_len = 1;
  } else {
    bad_term(option, t.text, "unknown operator; use one of < <= > >= == != ^=");
  }
  t.feature = std::string(trim(std::string_view(t.text).substr(0, pos)));
  std::string value(trim(rest.substr(op_len)));
  if (t.feature.empty()) bad_term(option, t.text, "missing feature name before the operator");
  if (value.empty()) bad_term(option, t.text, "missing value after the operator");
  if (value.find_first_of("<>=!^") != std::string::npos)
    bad_term(option, t.text, "more than one comparison operator in one condition; join with &&");

  if (t.feature == "id" || t.feature == "shape" || t.feature == "operator" ||
      t.feature == "replicate") {
    t.textual = true;
    if (t.op != Op::kEq && t.op != Op::kNe && t.op != Op::kPrefix)
      bad_term(option, t.text, "'" + t.feature + "' is text: only ==, != and ^= apply");
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') &&
        value.back() == value.front())
      value = value.substr(1, value.size() - 2);
    t.text_value = value;
    return t;
  }
  try {
    t.values = set.feature(t.feature);
  } catch (const std::invalid_argument& e) {
    bad_term(option, t.text, std::string(e.what()) + ", id, shape, operator, replicate");
  }
  if (t.op == Op::kPrefix)
    bad_term(option, t.text,
             "'^=' (starts with) compares text: id, shape, operator or replicate, not '" +
                 t.feature + "'");
  if (!parse_number(value, t.value) || !std::isfinite(t.value))
    bad_term(option, t.text, "value '" + value + "' is not a finite number (SI units, e.g. 3.5)");
  return t;
}

template <typename T>
bool compare(const T& a, Op op, const T& b) {
  switch (op) {
    case Op::kLt:
      return a < b;
    case Op::kLe:
      return a <= b;
    case Op::kGt:
      return a > b;
    case Op::kGe:
      return a >= b;
    case Op::kEq:
      return a == b;
    case Op::kNe:
      return a != b;
    case Op::kPrefix:
      // Text only: parse_term refuses it on a number.
      if constexpr (std::is_same_v<T, std::string>) return a.starts_with(b);
      return false;
  }
  return false;
}

}  // namespace

ImpactSet filter(const ImpactSet& set, const std::string& where, const std::string& option) {
  if (trim(where).empty()) return set;
  std::vector<Term> terms;
  for (const auto& piece : split_terms(where))
    terms.push_back(parse_term(piece, where, set, option));

  ImpactSet out = set;
  out.impacts.clear();
  out.comments.push_back("filter: " + where);
  for (std::size_t i = 0; i < set.impacts.size(); ++i) {
    const Impact& m = set.impacts[i];
    bool keep = true;
    for (const Term& t : terms) {
      if (t.textual) {
        const std::optional<std::string>& optional = t.feature == "operator" ? m.op : m.replicate;
        const std::string* field = t.feature == "id"      ? &m.id
                                   : t.feature == "shape" ? &m.shape
                                   : optional             ? &*optional
                                                          : nullptr;
        // A release without an operator (replicate label) matches no condition on it.
        keep = field != nullptr && compare(*field, t.op, t.text_value);
      } else {
        // A missing value (NaN) matches no condition, not even "!=".
        const double v = t.values[i];
        keep = !std::isnan(v) && compare(v, t.op, t.value);
      }
      if (!keep) break;
    }
    if (keep) out.impacts.push_back(m);
  }
  return out;
}

ImpactSet filter_nonempty(const ImpactSet& set, const std::string& where, const std::string& source,
                          const std::string& option) {
  ImpactSet out = filter(set, where, option);
  if (out.empty() && !set.empty() && !trim(where).empty())
    throw InputError("<command line>", 0, option,
                     "'" + where + "' keeps no release of " + source + " (" +
                         std::to_string(set.size()) + " releases)");
  return out;
}

std::vector<std::vector<std::size_t>> replicate_groups(const ImpactSet& set) {
  std::map<std::string, std::vector<std::size_t>> by_key;
  for (std::size_t i = 0; i < set.impacts.size(); ++i) {
    const Impact& im = set.impacts[i];
    std::string key;
    if (im.replicate) {
      key = "label " + *im.replicate;
    } else {
      // Shortest round-trip text: two states give one key exactly when they are equal.
      key = "state";
      for (double v : {im.vin[0], im.vin[1], im.vin[2], im.alpha_in.value_or(NAN)})
        key += ' ' + shortest_number(v);
    }
    by_key[key].push_back(i);
  }
  std::vector<std::vector<std::size_t>> groups;
  for (auto& [key, members] : by_key)
    if (members.size() >= 2) groups.push_back(std::move(members));
  return groups;
}

double pooled_variance(std::span<const double> x,
                       const std::vector<std::vector<std::size_t>>& groups) {
  double ss = 0;
  std::size_t dof = 0;
  for (const auto& members : groups) {
    if (members.size() < 2) continue;
    dof += members.size() - 1;
    double mean = 0;
    for (std::size_t i : members) mean += x[i];
    mean /= static_cast<double>(members.size());
    for (std::size_t i : members) ss += (x[i] - mean) * (x[i] - mean);
  }
  return dof > 0 ? ss / static_cast<double>(dof) : NAN;
}

Vel3 pooled_vout_sd(const ImpactSet& set, const std::vector<std::vector<std::size_t>>& groups) {
  Vel3 sd;
  std::vector<double> x(set.size());
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < set.size(); ++i) x[i] = set.impacts[i].vout[k];
    sd[k] = std::sqrt(pooled_variance(x, groups));
  }
  return sd;
}

}  // namespace ricochet
