#include "fit/fit_io.hpp"

#include <cmath>
#include <filesystem>
#include <map>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/json_number.hpp"
#include "stats/stats.hpp"

namespace ricochet::fit {
namespace {

constexpr const char* kSchema = "ricochet-calibration-1";

nlohmann::json vel(const Vel3& v) {
  return nlohmann::json::array({finite_or_null(v[0]), finite_or_null(v[1]), finite_or_null(v[2])});
}

int status_code(Identifiability s) {
  return static_cast<int>(s);
}

Identifiability status_from(int code) {
  switch (code) {
    case 0:
      return Identifiability::kIdentified;
    case 1:
      return Identifiability::kLowerBoundOnly;
    case 2:
      return Identifiability::kUpperBoundOnly;
    default:
      return Identifiability::kNotIdentified;
  }
}

std::vector<std::string> calibrated_names(const Model& model) {
  std::vector<std::string> out;
  for (std::size_t i : model.calibrated_indices()) out.emplace_back(model.spec(i).name);
  return out;
}

}  // namespace

nlohmann::json to_json(const ParameterInterval& iv) {
  return {{"value", finite_or_null(iv.value)},
          {"lo", finite_or_null(iv.lo)},
          {"hi", finite_or_null(iv.hi)},
          {"bounds", {finite_or_null(iv.bound_lo), finite_or_null(iv.bound_hi)}},
          {"status", identifiability_name(iv.status)},
          {"statement", iv.statement},
          {"unit", iv.unit}};
}

nlohmann::json to_json(const ReleaseFit& f) {
  nlohmann::json params = nlohmann::json::object(), fixed = nlohmann::json::object();
  for (std::size_t i = 0; i < f.names.size(); ++i) {
    const bool cal = std::find(f.calibrated.begin(), f.calibrated.end(), i) != f.calibrated.end();
    (cal ? params : fixed)[f.names[i]] = finite_or_null(f.params[i]);
  }
  nlohmann::json intervals = nlohmann::json::object(), ident = nlohmann::json::object(),
                 statements = nlohmann::json::object();
  for (const auto& iv : f.intervals) {
    intervals[iv.name] = {finite_or_null(iv.lo), finite_or_null(iv.hi)};
    ident[iv.name] = identifiability_name(iv.status);
    statements[iv.name] = iv.statement;
  }
  nlohmann::json j = {{"id", f.id},
                      {"params", params},
                      {"fixed", fixed},
                      {"intervals", intervals},
                      {"identifiability", ident},
                      {"statements", statements},
                      {"error", finite_or_null(f.error)},
                      {"threshold", finite_or_null(f.threshold)},
                      {"vout_measured", vel(f.measured)},
                      {"vout_simulated", vel(f.simulated)},
                      {"error_terms", vel(f.terms)},
                      {"status", status_name(f.status)},
                      {"start_errors", f.start_errors},
                      {"evaluations", f.evaluations},
                      {"seconds", f.seconds}};
  if (f.alpha_source != "none" && !f.alpha_source.empty()) {
    nlohmann::json a = {{"source", f.alpha_source},
                        {"value_rad", finite_or_null(f.alpha_rad)},
                        {"value_deg", finite_or_null(f.alpha_rad * 180.0 / M_PI)}};
    if (f.alpha_interval) {
      a["interval_rad"] = {finite_or_null(f.alpha_interval->lo),
                           finite_or_null(f.alpha_interval->hi)};
      a["identifiability"] = identifiability_name(f.alpha_interval->status);
      a["statement"] = f.alpha_interval->statement;
    }
    j["alpha_in"] = a;
  }
  return j;
}

nlohmann::json summary_json(const std::vector<ReleaseFit>& fits) {
  nlohmann::json out = nlohmann::json::object();
  if (fits.empty()) return out;
  // Parameter names in model order, calibrated only.
  std::vector<std::string> names;
  for (std::size_t i : fits.front().calibrated) names.push_back(fits.front().names[i]);
  for (const auto& name : names) {
    std::vector<double> all, identified;
    std::map<std::string, int> counts = {
        {"identified", 0}, {"lower_bound_only", 0}, {"upper_bound_only", 0}, {"not_identified", 0}};
    std::vector<double> los, his;
    for (const auto& f : fits) {
      if (f.id.empty()) continue;
      all.push_back(f.value(name));
      if (const ParameterInterval* iv = f.interval(name)) {
        ++counts[identifiability_name(iv->status)];
        if (iv->status == Identifiability::kIdentified) identified.push_back(f.value(name));
        los.push_back(iv->lo);
        his.push_back(iv->hi);
      }
    }
    const stats::Summary s = stats::summarize(all);
    nlohmann::json j = {
        {"mean", finite_or_null(s.mean)}, {"std", finite_or_null(s.std)}, {"n", s.n}};
    if (!los.empty()) {
      const stats::Summary si = stats::summarize(identified);
      j["counts"] = counts;
      j["mean_identified"] = finite_or_null(si.mean);
      j["std_identified"] = finite_or_null(si.std);
      j["n_identified"] = si.n;
      j["mean_lo"] = finite_or_null(stats::summarize(los).mean);
      j["mean_hi"] = finite_or_null(stats::summarize(his).mean);
    }
    out[name] = j;
  }
  std::vector<double> alpha;
  for (const auto& f : fits)
    if (f.alpha_source == "fitted") alpha.push_back(f.alpha_rad * 180.0 / M_PI);
  if (!alpha.empty()) {
    const stats::Summary s = stats::summarize(alpha);
    out["alpha_in_deg"] = {
        {"mean", finite_or_null(s.mean)}, {"std", finite_or_null(s.std)}, {"n", s.n}};
  }
  return out;
}

nlohmann::json to_json(const PopulationFit& p) {
  nlohmann::json params = nlohmann::json::object();
  for (std::size_t i : p.calibrated) params[p.names[i]] = finite_or_null(p.params[i]);
  nlohmann::json intervals = nlohmann::json::object(), ident = nlohmann::json::object(),
                 statements = nlohmann::json::object();
  for (const auto& iv : p.intervals) {
    intervals[iv.name] = {finite_or_null(iv.lo), finite_or_null(iv.hi)};
    ident[iv.name] = identifiability_name(iv.status);
    statements[iv.name] = iv.statement;
  }
  return {
      {"params", params},
      {"intervals", intervals},
      {"identifiability", ident},
      {"statements", statements},
      {"error", finite_or_null(p.error)},
      {"mean_error", finite_or_null(p.error / std::max<std::size_t>(1, p.release_errors.size()))},
      {"threshold", finite_or_null(p.threshold)},
      {"start_errors", p.start_errors},
      {"evaluations", p.evaluations},
      {"seconds", p.seconds}};
}

nlohmann::json to_json(const FitOptions& o) {
  return {{"dt_s", o.engine.dt_s},
          {"max_time_s", o.engine.max_time_s},
          {"gravity_mps2", o.engine.gravity_mps2},
          {"initial_gap_m", o.engine.initial_gap_m},
          {"flat_ground", o.engine.ground.flat()},
          {"error_floor", {o.error.floor[0], o.error.floor[1], o.error.floor[2]}},
          {"error_penetration", o.error.penetration},
          {"error_contact_duration", o.error.contact_duration},
          {"error_penetration_floor_m", o.error.penetration_floor_m},
          {"error_contact_duration_floor_s", o.error.contact_duration_floor_s},
          {"error_penetration_scale_m", o.error.penetration_scale_m},
          {"error_contact_duration_scale_s", o.error.contact_duration_scale_s},
          {"sigma_penetration_m", o.sigma_penetration_m},
          {"sigma_contact_duration_s", o.sigma_contact_duration_s},
          {"seed", o.seed},
          {"starts", o.starts},
          {"design_points", o.design_points},
          {"max_evaluations", o.max_evaluations},
          {"xtol", o.xtol},
          {"alpha_mode", alpha_mode_name(o.alpha.mode)},
          {"alpha_min_rad", o.alpha.min_rad},
          {"alpha_max_rad", o.alpha.max_rad},
          {"alpha_marginal_points", o.alpha.marginal_points},
          {"alpha_polish_points", o.alpha.polish_points},
          {"alpha_polish_ends", o.alpha.polish_ends},
          {"alpha_rotate", o.alpha.rotate},
          {"intervals", o.intervals},
          {"sigma", {o.sigma[0], o.sigma[1], o.sigma[2]}},
          {"threshold_scale", o.threshold_scale},
          {"interval_resolution", o.interval_resolution}};
}

// ---------------------------------------------------------------------------------------------

struct ReleaseFitStore::Impl {
  std::string path, group;
  h5::File file;
  std::vector<std::string> names, calibrated;
  std::size_t starts = 0, columns = 0;

  Impl(std::string p, std::string g, h5::File::Mode mode)
      : path(std::move(p)), group(std::move(g)), file(path, mode) {}

  std::vector<std::string> column_names() const {
    std::vector<std::string> c = {"index",        "error",        "threshold",   "status",
                                  "evaluations",  "seconds",      "alpha_rad",   "alpha_lo_rad",
                                  "alpha_hi_rad", "alpha_status", "vout_meas_x", "vout_meas_y",
                                  "vout_meas_w",  "vout_sim_x",   "vout_sim_y",  "vout_sim_w"};
    for (const auto& n : names) c.push_back(n);
    for (const auto& n : calibrated) {
      c.push_back(n + "_lo");
      c.push_back(n + "_hi");
      c.push_back(n + "_status");
    }
    for (std::size_t s = 0; s < starts; ++s) c.push_back("start_error_" + std::to_string(s));
    return c;
  }
};

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= s.size()) {
    const std::size_t comma = s.find(',', at);
    out.push_back(s.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return out;
}

}  // namespace

ReleaseFitStore::ReleaseFitStore(const std::string& path, const Model& model, const Shape& shape,
                                 const ImpactSet& set, const FitOptions& options, bool resume,
                                 const std::string& group) {
  const std::string g = "/" + group;
  const std::string model_json = model.to_json().dump();
  const std::string settings = to_json(options).dump();
  const bool exists = std::filesystem::exists(path);
  if (resume && exists) {
    // Same run? Compare what determines the results.
    {
      h5::File f(path, h5::File::Mode::kRead);
      if (!f.exists(g) || !f.has_attr(g, "schema") || f.attr_string(g, "schema") != kSchema)
        throw InputError(path, 0, group, "cannot resume: not a Ricochet calibration file");
      const std::pair<const char*, std::string> checks[] = {{"model_json", model_json},
                                                            {"settings_json", settings},
                                                            {"shape", shape.name},
                                                            {"data", set.source}};
      for (const auto& [attr, want] : checks)
        if (f.attr_string(g, attr) != want)
          throw InputError(path, 0, std::string(group) + "@" + attr,
                           "cannot resume: the file was written with a different " +
                               std::string(attr) + "; remove it or choose another --out");
    }
    existing_ = read_release_fits(path, group);
    for (const auto& f : existing_) done_.insert(f.id);
    impl_ = new Impl(path, g, h5::File::Mode::kReadWrite);
  } else {
    if (exists) std::filesystem::remove(path);
    write_impact_set_h5(set, path, group + "/impacts");
    impl_ = new Impl(path, g, h5::File::Mode::kReadWrite);
    h5::File& f = impl_->file;
    f.set_attr(g, "schema", kSchema);
    f.set_attr(g, "shape", shape.name);
    f.set_attr(g, "data", set.source);
    f.set_attr(g, "model_json", model_json);
    f.set_attr(g, "model_toml", model.to_toml());
    f.set_attr(g, "settings_json", settings);
    f.set_attr(g, "seed", static_cast<double>(options.seed));
    f.set_attr(g, "alpha_mode", alpha_mode_name(options.alpha.mode));
    f.set_attr(
        g, "equation",
        "Garcia et al. (2020) Eq. 7: sum_k ((V_k^sim - V_k^meas) / max(|V_k^meas|, floor_k))^2");
    f.write_strings(g + "/names", model.parameter_names());
    f.write_strings(g + "/calibrated", calibrated_names(model));
  }
  impl_->names = model.parameter_names();
  impl_->calibrated = calibrated_names(model);
  impl_->starts = static_cast<std::size_t>(std::max(options.starts, 1));
  impl_->columns = impl_->column_names().size();
  impl_->file.set_attr(g + "/releases", "columns", join(impl_->column_names()));
  impl_->file.flush();
}

ReleaseFitStore::~ReleaseFitStore() {
  delete impl_;
}

void ReleaseFitStore::append(std::size_t index, const ReleaseFit& fit) {
  Impl& s = *impl_;
  std::vector<double> row = {static_cast<double>(index),
                             fit.error,
                             fit.threshold,
                             static_cast<double>(static_cast<int>(fit.status)),
                             static_cast<double>(fit.evaluations),
                             fit.seconds,
                             fit.alpha_rad,
                             fit.alpha_interval ? fit.alpha_interval->lo : NAN,
                             fit.alpha_interval ? fit.alpha_interval->hi : NAN,
                             fit.alpha_interval ? status_code(fit.alpha_interval->status) : -1.0,
                             fit.measured[0],
                             fit.measured[1],
                             fit.measured[2],
                             fit.simulated[0],
                             fit.simulated[1],
                             fit.simulated[2]};
  row.insert(row.end(), fit.params.begin(), fit.params.end());
  std::vector<std::string> statements;
  for (const auto& name : s.calibrated) {
    const ParameterInterval* iv = fit.interval(name);
    row.push_back(iv ? iv->lo : NAN);
    row.push_back(iv ? iv->hi : NAN);
    row.push_back(iv ? status_code(iv->status) : -1.0);
    statements.push_back(iv ? iv->statement : "");
  }
  for (std::size_t k = 0; k < s.starts; ++k)
    row.push_back(k < fit.start_errors.size() ? fit.start_errors[k] : NAN);
  s.file.append_rows(s.group + "/releases/rows", row, s.columns);
  s.file.append_strings(s.group + "/releases/id", {fit.id});
  s.file.append_strings(s.group + "/releases/statements", statements);
  s.file.append_strings(s.group + "/releases/alpha_source", {fit.alpha_source});
  auto write_profile = [&](const ParameterInterval& iv) {
    std::vector<double> p;
    for (const auto& pt : iv.profile) p.insert(p.end(), pt.begin(), pt.end());
    if (!p.empty())
      s.file.write(s.group + "/profiles/" + fit.id + "/" + iv.name, p, {iv.profile.size(), 2});
  };
  for (const auto& iv : fit.intervals) write_profile(iv);
  if (fit.alpha_interval) write_profile(*fit.alpha_interval);
  s.file.flush();
}

void ReleaseFitStore::write_summary(const std::vector<ReleaseFit>& fits,
                                    const PopulationFit* population, double seconds) {
  Impl& s = *impl_;
  const std::string g = s.group + "/summary";
  s.file.remove(g);
  s.file.create_group(g);
  s.file.set_attr(g, "json", summary_json(fits).dump());
  s.file.set_attr(g, "seconds", seconds);
  if (population) {
    const std::string p = s.group + "/population";
    s.file.remove(p);
    s.file.write(p + "/params", population->params);
    s.file.write(p + "/release_errors", population->release_errors);
    s.file.set_attr(p, "json", to_json(*population).dump());
  }
  s.file.flush();
}

std::vector<ReleaseFit> read_release_fits(const std::string& path, const std::string& group) {
  std::unique_ptr<h5::File> file;
  try {
    file = std::make_unique<h5::File>(path, h5::File::Mode::kRead);
  } catch (const std::runtime_error&) {
    throw InputError(path, 0, group, "cannot open as HDF5 (missing file or not an HDF5 file)");
  }
  const std::string g = "/" + group;
  if (!file->exists(g) || !file->has_attr(g, "schema") || file->attr_string(g, "schema") != kSchema)
    throw InputError(path, 0, group, "no Ricochet calibration group /" + group);
  std::vector<ReleaseFit> out;
  if (!file->exists(g + "/releases/rows")) return out;
  const std::vector<std::string> names = file->read_strings(g + "/names");
  const std::vector<std::string> calibrated = file->read_strings(g + "/calibrated");
  const std::vector<std::string> columns = split(file->attr_string(g + "/releases", "columns"));
  std::vector<std::size_t> dims;
  const std::vector<double> rows = file->read_doubles(g + "/releases/rows", &dims);
  const std::vector<std::string> ids = file->read_strings(g + "/releases/id");
  const std::vector<std::string> statements = file->read_strings(g + "/releases/statements");
  const std::size_t C = dims.size() == 2 ? dims[1] : 0;
  if (C != columns.size() || ids.size() * C != rows.size())
    throw InputError(path, 0, group + "/releases", "inconsistent release table");
  std::map<std::string, std::size_t> col;
  for (std::size_t k = 0; k < columns.size(); ++k) col[columns[k]] = k;
  const std::vector<std::string> alpha_sources = file->read_strings(g + "/releases/alpha_source");
  for (std::size_t r = 0; r < ids.size(); ++r) {
    const double* row = rows.data() + r * C;
    auto at = [&](const std::string& c) { return row[col.at(c)]; };
    ReleaseFit f;
    f.id = ids[r];
    f.names = names;
    for (const auto& n : names) f.params.push_back(at(n));
    for (const auto& n : calibrated)
      f.calibrated.push_back(
          static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin()));
    f.error = at("error");
    f.threshold = at("threshold");
    f.status = static_cast<CollisionStatus>(static_cast<int>(at("status")));
    f.evaluations = static_cast<int>(at("evaluations"));
    f.seconds = at("seconds");
    f.alpha_rad = at("alpha_rad");
    f.measured = {at("vout_meas_x"), at("vout_meas_y"), at("vout_meas_w")};
    f.simulated = {at("vout_sim_x"), at("vout_sim_y"), at("vout_sim_w")};
    for (std::size_t s = 0; col.count("start_error_" + std::to_string(s)); ++s) {
      const double e = at("start_error_" + std::to_string(s));
      if (std::isfinite(e)) f.start_errors.push_back(e);
    }
    f.alpha_source = r < alpha_sources.size() ? alpha_sources[r] : "";
    for (std::size_t k = 0; k < calibrated.size(); ++k) {
      const std::string& n = calibrated[k];
      const int code = static_cast<int>(at(n + "_status"));
      if (code < 0) continue;
      ParameterInterval iv;
      iv.name = n;
      iv.value = at(n);
      iv.lo = at(n + "_lo");
      iv.hi = at(n + "_hi");
      iv.status = status_from(code);
      iv.statement = r * calibrated.size() + k < statements.size()
                         ? statements[r * calibrated.size() + k]
                         : "";
      f.intervals.push_back(iv);
    }
    const double alo = at("alpha_lo_rad"), ahi = at("alpha_hi_rad");
    if (std::isfinite(alo)) {
      ParameterInterval iv;
      iv.name = "alpha_in";
      iv.unit = "rad";
      iv.value = f.alpha_rad;
      iv.lo = alo;
      iv.hi = ahi;
      iv.status = status_from(static_cast<int>(at("alpha_status")));
      f.alpha_interval = iv;
    }
    out.push_back(std::move(f));
  }
  return out;
}

void write_csv(const std::string& path, const std::vector<ReleaseFit>& fits) {
  CsvTable t;
  t.comment("ricochet calibrate: per-release optimum of paper Eq. 7 and near-optimal intervals");
  std::vector<std::string> header = {"id", "error", "threshold", "alpha_rad"};
  const ReleaseFit* first = nullptr;
  for (const auto& f : fits)
    if (!f.id.empty()) first = &f;
  if (first)
    for (std::size_t i : first->calibrated)
      for (const char* suffix : {"", "_lo", "_hi", "_status"})
        header.push_back(first->names[i] + suffix);
  t.row(header);
  for (const auto& f : fits) {
    if (f.id.empty()) continue;
    std::vector<std::string> row = {f.id, CsvTable::num(f.error), CsvTable::num(f.threshold),
                                    CsvTable::num(f.alpha_rad)};
    for (std::size_t i : f.calibrated) {
      const ParameterInterval* iv = f.interval(f.names[i]);
      row.push_back(CsvTable::num(f.params[i]));
      row.push_back(iv ? CsvTable::num(iv->lo) : "");
      row.push_back(iv ? CsvTable::num(iv->hi) : "");
      row.push_back(iv ? identifiability_name(iv->status) : "");
    }
    t.row(row);
  }
  t.write(path);
}

}  // namespace ricochet::fit
