#include "uq_options.hpp"

#include <algorithm>
#include <map>

#include "common/error.hpp"

namespace ricochet::cli {

void add_input_options(CLI::App* sub, InputOptions& o) {
  sub->add_option("--range", o.ranges,
                  "Uniform range of a parameter NAME=LO:HI (repeatable); default: the paper's "
                  "ranges, else the calibration bounds");
  sub->add_option("--fix", o.fixed, "Keep a calibrated parameter at its model value (repeatable)");
}

std::vector<uq::ParameterInput> InputOptions::build(const Model& model) const {
  std::vector<std::pair<std::string, std::pair<double, double>>> order;
  auto put = [&](const std::string& name, std::pair<double, double> r) {
    for (auto& [n, range] : order)
      if (n == name) {
        range = r;
        return;
      }
    order.push_back({name, r});
  };
  for (std::size_t i : model.calibrated_indices()) {
    const std::string name(model.spec(i).name);
    const auto p = uq::paper_range(model.spec(i).role);
    put(name, p ? *p : std::make_pair(model.lower(i), model.upper(i)));
  }
  for (const auto& text : ranges) {
    const auto [name, r] = uq::parse_range(text, "--range");
    std::size_t i = 0;
    try {
      i = model.index(name);
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "--range", e.what());
    }
    const ParameterSpec& s = model.spec(i);
    if (r.first < s.lower || r.second > s.upper)
      throw InputError("<command line>", 0, "--range",
                       text + " leaves the bounds of " + name + " [" + std::to_string(s.lower) +
                           ", " + std::to_string(s.upper) + "] " + std::string(s.unit));
    put(name, r);
  }
  for (const auto& name : fixed) {
    const auto it =
        std::find_if(order.begin(), order.end(), [&](const auto& e) { return e.first == name; });
    if (it == order.end())
      throw InputError("<command line>", 0, "--fix", "'" + name + "' is not a varied parameter");
    order.erase(it);
  }
  std::vector<uq::ParameterInput> out;
  for (const auto& [name, r] : order)
    out.push_back({name, uq::Distribution::uniform(r.first, r.second)});
  if (out.empty())
    throw InputError("<command line>", 0, "--range", "no parameter varies (all fixed?)");
  return out;
}

}  // namespace ricochet::cli
