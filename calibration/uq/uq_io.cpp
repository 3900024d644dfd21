#include "uq/uq_io.hpp"

#include <cmath>
#include <filesystem>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/json_number.hpp"
#include "stats/stats.hpp"

namespace ricochet::uq {
namespace {

constexpr const char* kMcSchema = "ricochet-montecarlo-1";
constexpr const char* kSobolSchema = "ricochet-sobol-1";
constexpr std::size_t kExtraColumns = 8;  // vin (3), alpha, vout (3), status

}  // namespace

nlohmann::json components_json(const Vel3& v) {
  return {{"vx", finite_or_null(v[0])}, {"vy", finite_or_null(v[1])}, {"w", finite_or_null(v[2])}};
}

nlohmann::json inputs_json(const std::vector<ParameterInput>& inputs) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& in : inputs)
    j[in.name] = {{"distribution", in.distribution.description()},
                  {"lo", finite_or_null(in.distribution.lower())},
                  {"hi", finite_or_null(in.distribution.upper())}};
  return j;
}

nlohmann::json to_json(const SobolResult& r) {
  nlohmann::json first, second, total, ifirst, isecond, itotal;
  for (std::size_t o = 0; o < r.outputs.size(); ++o) {
    const std::string& out = r.outputs[o];
    first[out] = nlohmann::json::object();
    total[out] = nlohmann::json::object();
    second[out] = nlohmann::json::object();
    for (std::size_t i = 0; i < r.inputs.size(); ++i) {
      first[out][r.inputs[i]] = finite_or_null(r.first[o][i].value);
      total[out][r.inputs[i]] = finite_or_null(r.total[o][i].value);
      ifirst[out][r.inputs[i]] = {finite_or_null(r.first[o][i].lo),
                                  finite_or_null(r.first[o][i].hi)};
      itotal[out][r.inputs[i]] = {finite_or_null(r.total[o][i].lo),
                                  finite_or_null(r.total[o][i].hi)};
      for (std::size_t j = i + 1; j < r.inputs.size(); ++j) {
        const std::string pair = r.inputs[i] + "-" + r.inputs[j];
        second[out][pair] = finite_or_null(r.second[o][i][j].value);
        isecond[out][pair] = {finite_or_null(r.second[o][i][j].lo),
                              finite_or_null(r.second[o][i][j].hi)};
      }
    }
  }
  return {
      {"first_order", first},
      {"second_order", second},
      {"total_order", total},
      {"intervals", {{"first_order", ifirst}, {"second_order", isecond}, {"total_order", itotal}}},
      {"estimator", r.estimator},
      {"base_size", r.base_size},
      {"evaluations", r.evaluations},
      {"confidence", r.confidence},
      {"variance", r.variance},
      {"seconds", r.seconds}};
}

nlohmann::json to_json(const MonteCarloOptions& o, const std::string& incident_source) {
  nlohmann::json j = {{"runs", o.runs},
                      {"seed", o.seed},
                      {"dt_s", o.engine.dt_s},
                      {"max_time_s", o.engine.max_time_s},
                      {"alpha_min_rad", o.alpha_min_rad},
                      {"alpha_max_rad", o.alpha_max_rad},
                      {"chunk", o.chunk}};
  if (o.incident)
    j["incident"] = {{"resampled_from", incident_source}, {"releases", o.incident->size()}};
  else
    j["incident"] = {{"fixed", {o.vin[0], o.vin[1], o.vin[2]}}};
  return j;
}

struct MonteCarloStore::Impl {
  h5::File file;
  std::size_t columns = 0;
  explicit Impl(const std::string& path, h5::File::Mode mode) : file(path, mode) {}
};

MonteCarloStore::MonteCarloStore(const std::string& path, const Model& model, const Shape& shape,
                                 const std::vector<ParameterInput>& inputs,
                                 const MonteCarloOptions& options,
                                 const std::string& incident_source, bool resume) {
  const std::string g = "/montecarlo";
  const std::string model_json = model.to_json().dump();
  const std::string settings = to_json(options, incident_source).dump();
  const std::string ins = inputs_json(inputs).dump();
  std::vector<std::string> columns;
  for (const auto& in : inputs) columns.push_back(in.name);
  for (const char* c : {"vin_x", "vin_y", "win", "alpha_rad", "vout_x", "vout_y", "wout", "status"})
    columns.emplace_back(c);
  std::string column_list;
  for (const auto& c : columns) column_list += (column_list.empty() ? "" : ",") + c;
  if (resume && std::filesystem::exists(path)) {
    impl_ = new Impl(path, h5::File::Mode::kReadWrite);
    h5::File& f = impl_->file;
    if (!f.exists(g) || !f.has_attr(g, "schema") || f.attr_string(g, "schema") != kMcSchema)
      throw InputError(path, 0, "montecarlo", "cannot resume: not a Ricochet Monte Carlo file");
    const std::pair<const char*, std::string> checks[] = {{"model_json", model_json},
                                                          {"settings_json", settings},
                                                          {"inputs_json", ins},
                                                          {"shape", shape.name}};
    for (const auto& [attr, want] : checks)
      if (f.attr_string(g, attr) != want)
        throw InputError(path, 0, std::string("montecarlo@") + attr,
                         "cannot resume: the file was written with a different " +
                             std::string(attr) + "; remove it or choose another --out");
    if (f.exists(g + "/runs")) {
      std::vector<std::size_t> dims;
      f.read_doubles(g + "/runs", &dims);
      done_ = dims.empty() ? 0 : dims[0];
    }
  } else {
    if (std::filesystem::exists(path)) std::filesystem::remove(path);
    impl_ = new Impl(path, h5::File::Mode::kTruncate);
    h5::File& f = impl_->file;
    f.set_attr(g, "schema", kMcSchema);
    f.set_attr(g, "shape", shape.name);
    f.set_attr(g, "model_json", model_json);
    f.set_attr(g, "model_toml", model.to_toml());
    f.set_attr(g, "settings_json", settings);
    f.set_attr(g, "inputs_json", ins);
    f.set_attr(g, "seed", static_cast<double>(options.seed));
    std::vector<std::string> varied;
    for (const auto& in : inputs) varied.push_back(in.name);
    f.write_strings(g + "/varied", varied);
    f.set_attr(g, "run_columns", column_list);
  }
  impl_->columns = columns.size();
  impl_->file.flush();
}

MonteCarloStore::~MonteCarloStore() {
  delete impl_;
}

void MonteCarloStore::load(MonteCarloResult& r) const {
  if (done_ == 0) return;
  std::vector<std::size_t> dims;
  const std::vector<double> rows = impl_->file.read_doubles("/montecarlo/runs", &dims);
  const std::size_t C = impl_->columns, V = C - kExtraColumns;
  for (std::size_t i = 0; i < done_ && i < r.size(); ++i) {
    const double* row = rows.data() + i * C;
    for (std::size_t k = 0; k < V; ++k) r.inputs[i * V + k] = row[k];
    r.vin[i] = {row[V], row[V + 1], row[V + 2]};
    r.alpha_rad[i] = row[V + 3];
    r.vout[i] = {row[V + 4], row[V + 5], row[V + 6]};
    r.status[i] = static_cast<int>(row[V + 7]);
  }
}

void MonteCarloStore::append(std::size_t begin, std::size_t end, const MonteCarloResult& r) {
  const std::size_t C = impl_->columns, V = C - kExtraColumns;
  std::vector<double> rows;
  rows.reserve((end - begin) * C);
  for (std::size_t i = begin; i < end; ++i) {
    for (std::size_t k = 0; k < V; ++k) rows.push_back(r.inputs[i * V + k]);
    rows.insert(rows.end(), r.vin[i].begin(), r.vin[i].end());
    rows.push_back(r.alpha_rad[i]);
    rows.insert(rows.end(), r.vout[i].begin(), r.vout[i].end());
    rows.push_back(static_cast<double>(r.status[i]));
  }
  impl_->file.append_rows("/montecarlo/runs", rows, C);
  impl_->file.flush();
  done_ = end;
}

void MonteCarloStore::write_json(const std::string& attribute, const nlohmann::json& doc) {
  impl_->file.set_attr("/montecarlo", attribute, doc.dump());
  impl_->file.flush();
}

void write_sobol_h5(const std::string& path, const SobolResult& r, const Model& model,
                    const Shape& shape, const std::vector<ParameterInput>& inputs,
                    const nlohmann::json& settings) {
  h5::File f(path, h5::File::Mode::kTruncate);
  const std::string g = "/sobol";
  f.set_attr(g, "schema", kSobolSchema);
  f.set_attr(g, "shape", shape.name);
  f.set_attr(g, "model_json", model.to_json().dump());
  f.set_attr(g, "model_toml", model.to_toml());
  f.set_attr(g, "settings_json", settings.dump());
  f.set_attr(g, "inputs_json", inputs_json(inputs).dump());
  f.set_attr(g, "estimator", r.estimator);
  f.set_attr(g, "json", to_json(r).dump());
  f.write_strings(g + "/inputs", r.inputs);
  f.write_strings(g + "/outputs", r.outputs);
  const std::size_t O = r.outputs.size(), D = r.inputs.size();
  auto matrix = [&](auto get) {
    std::vector<double> v;
    for (std::size_t o = 0; o < O; ++o)
      for (std::size_t i = 0; i < D; ++i) v.push_back(get(o, i));
    return v;
  };
  f.write(g + "/first", matrix([&](auto o, auto i) { return r.first[o][i].value; }), {O, D});
  f.write(g + "/first_lo", matrix([&](auto o, auto i) { return r.first[o][i].lo; }), {O, D});
  f.write(g + "/first_hi", matrix([&](auto o, auto i) { return r.first[o][i].hi; }), {O, D});
  f.write(g + "/total", matrix([&](auto o, auto i) { return r.total[o][i].value; }), {O, D});
  f.write(g + "/total_lo", matrix([&](auto o, auto i) { return r.total[o][i].lo; }), {O, D});
  f.write(g + "/total_hi", matrix([&](auto o, auto i) { return r.total[o][i].hi; }), {O, D});
  std::vector<double> s2, s2lo, s2hi;
  for (std::size_t o = 0; o < O; ++o)
    for (std::size_t i = 0; i < D; ++i)
      for (std::size_t j = 0; j < D; ++j) {
        const bool off = i != j;
        s2.push_back(off ? r.second[o][i][j].value : NAN);
        s2lo.push_back(off ? r.second[o][i][j].lo : NAN);
        s2hi.push_back(off ? r.second[o][i][j].hi : NAN);
      }
  f.write(g + "/second", s2, {O, D, D});
  f.write(g + "/second_lo", s2lo, {O, D, D});
  f.write(g + "/second_hi", s2hi, {O, D, D});
  f.write(g + "/variance", r.variance);
  if (!r.design_x.empty()) {
    f.write(g + "/design_x", r.design_x, {r.evaluations, D});
    f.write(g + "/design_y", r.design_y, {r.evaluations, O});
  }
  f.flush();
}

nlohmann::json moments_json(const MonteCarloResult& mc) {
  nlohmann::json mean, sd;
  for (int k = 0; k < 3; ++k) {
    const stats::Summary s = stats::summarize(mc.component(k));
    mean[kComponentNames[k]] = s.mean;
    sd[kComponentNames[k]] = s.std;
  }
  return {{"mean", mean}, {"std", sd}};
}

void write_runs_csv(const std::string& path, const MonteCarloResult& result) {
  CsvTable t;
  t.comment("ricochet montecarlo: one row per run");
  std::vector<std::string> header(result.varied.begin(), result.varied.end());
  for (const char* c : {"vin_x[m/s]", "vin_y[m/s]", "win[rad/s]", "alpha_in[rad]", "vout_x[m/s]",
                        "vout_y[m/s]", "wout[rad/s]", "status"})
    header.push_back(c);
  t.row(header);
  const std::size_t V = result.varied.size();
  const auto num = CsvTable::num;
  for (std::size_t i = 0; i < result.size(); ++i) {
    std::vector<std::string> row;
    for (std::size_t k = 0; k < V; ++k) row.push_back(num(result.inputs[i * V + k]));
    for (double v : {result.vin[i][0], result.vin[i][1], result.vin[i][2], result.alpha_rad[i],
                     result.vout[i][0], result.vout[i][1], result.vout[i][2]})
      row.push_back(num(v));
    row.push_back(std::to_string(result.status[i]));
    t.row(row);
  }
  t.write(path);
}

}  // namespace ricochet::uq
