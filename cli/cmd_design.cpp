// `ricochet design SET --budget N --range NAME=A:B ... --out plan.csv`: the throws that would
// decide between rival laws, T-optimal max-min over the pairs of rivals (docs/commands/
// design.md; the method: calibration/diagnosis/throw_design.hpp).
#include "cmd_design.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <iostream>
#include <memory>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/inputs.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {

void parse_range(const std::string& text, diagnosis::WideBox& box, std::array<bool, 3>& given) {
  const auto bad = [&](const std::string& what) {
    return InputError("<command line>", 0, "--range", "'" + text + "': " + what);
  };
  const std::size_t eq = text.find('='), colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos)
    throw bad("expected NAME=A:B with NAME vin_x, vin_y or win (SI units), e.g. vin_y=-5:-1");
  const std::string name = text.substr(0, eq);
  const auto number = [&](std::string_view cell) {
    if (cell.starts_with('+')) cell.remove_prefix(1);
    double x = NAN;
    const auto [end, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), x);
    if (cell.empty() || ec != std::errc() || end != cell.data() + cell.size() || !std::isfinite(x))
      throw bad("'" + std::string(cell) + "' is not a finite number");
    return x;
  };
  const double lo = number(std::string_view(text).substr(eq + 1, colon - eq - 1));
  const double hi = number(std::string_view(text).substr(colon + 1));
  std::array<double, 2>* range = nullptr;
  int k = 0;
  if (name == "vin_x")
    range = &box.vin_x, k = kVx;
  else if (name == "vin_y")
    range = &box.vin_y, k = kVy;
  else if (name == "win")
    range = &box.win, k = kW;
  else
    throw bad("unknown component '" + name + "'; use vin_x [m/s], vin_y [m/s] or win [rad/s]");
  if (given[k]) throw bad(name + " is given twice");
  given[k] = true;
  *range = {lo, hi};
}

namespace {

// The command line's names of the design options it binds (their ranges: DesignOptions::problems).
const OptionNames kDesignNames = {{"budget", "--budget"},
                                  {"candidates", "--candidates"},
                                  {"alpha", "--alpha"},
                                  {"max_passes", "--passes"},
                                  {"assess.fit.alpha.marginal_points", "--orientations"},
                                  {"assess.fit.alpha.polish_points", "--polish-orientations"},
                                  {"assess.fit.engine.dt_s", "--dt"}};

struct DesignCliOptions {
  std::string data;
  std::string where;
  ModelOptions model;
  std::vector<std::string> ranges;
  std::vector<std::string> rivals;
  diagnosis::DesignOptions design;
  std::uint64_t seed = diagnosis::DesignOptions{}.seed;
  int threads = diagnosis::DesignOptions{}.assess.fit.threads;
  int orientations = diagnosis::DesignOptions{}.assess.fit.alpha.marginal_points;
  int polish_orientations = diagnosis::DesignOptions{}.assess.fit.alpha.polish_points;
  OutputOptions output;
  bool shape_given = false;
};

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

void print_text(const diagnosis::ThrowDesign& d, const std::string& data, const std::string& out) {
  std::cout << fmt::format(
      "{}: {} releases of shape {}; {} new throws chosen among {} candidates ({} without a "
      "rebound under some rival)\n",
      data, d.releases, d.shape, d.plan.size(), d.candidates, d.excluded);
  std::cout << fmt::format(
      "box: vin_x [{:g}, {:g}] m/s, vin_y [{:g}, {:g}] m/s, win [{:g}, {:g}] rad/s\n\n",
      d.box.vin_x[0], d.box.vin_x[1], d.box.vin_y[0], d.box.vin_y[1], d.box.win[0], d.box.win[1]);
  std::cout << "rivals (calibrated on the set):\n";
  for (const auto& r : d.rivals) {
    // The base model's law is long (every effect's equation): its calibrated values say it.
    std::string law = r.law;
    if (r.effects.empty()) {
      law = "the base model:";
      for (std::size_t i : r.model.calibrated_indices())
        law += fmt::format(" {} = {:.4g}", r.model.spec(i).name, r.model.values()[i]);
    }
    std::cout << fmt::format("  {:<34} error {:<8.4g} {}\n", r.name, r.error, law);
  }
  std::cout << fmt::format(
      "\n{:<48}{:>12}{:>8}{:>12}{:>8}{:>12}{:>8}\n",
      "pair (noncentrality lambda, power at level " + fmt::format("{:.3g})", d.test_level), "plan",
      "", "uniform", "", "set only", "");
  for (const auto& p : d.pairs) {
    const std::string name =
        d.rivals[p.a].name + " vs " + d.rivals[p.b].name + (p.nested ? " (nested)" : "");
    if (p.indistinguishable) {
      std::cout << fmt::format("{:<48}  indistinguishable at the set's calibration\n", name);
      continue;
    }
    if (p.beyond_budget) {
      std::cout << fmt::format(
          "{:<48}  beyond the budget: its own best plan reaches power {:.3f} (lambda {:.3g})\n",
          name, p.alone.power, p.alone.lambda);
      continue;
    }
    std::cout << fmt::format("{:<48}{:>12.4g}{:>8.3f}{:>12.4g}{:>8.3f}{:>12.4g}{:>8.3f}\n", name,
                             p.plan.lambda, p.plan.power, p.uniform.lambda, p.uniform.power,
                             p.set.lambda, p.set.power);
  }
  std::cout << fmt::format("{:<48}{:>12.4g}{:>8.3f}{:>12.4g}{:>8.3f}{:>12.4g}{:>8.3f}\n",
                           "weakest pair", d.min_plan.lambda, d.min_plan.power,
                           d.min_uniform.lambda, d.min_uniform.power, d.min_set.lambda,
                           d.min_set.power);
  std::cout << fmt::format(
      "\n({:.2f} s: calibration {:.2f} s, predictions {:.2f} s, selection {:.2f} s with {} "
      "exchange passes, {} swaps)\n",
      d.seconds, d.calibration_s, d.prediction_s, d.selection_s, d.passes, d.swaps);
  std::cout << "wrote " << out << "\n";
}

void run(DesignCliOptions& o) {
  require_out_extension(o.output, {".csv"});
  // The box: the ranges given, the set's own span for the others.
  diagnosis::WideBox given_box;
  std::array<bool, 3> given{};
  for (const auto& r : o.ranges) parse_range(r, given_box, given);
  diagnosis::DesignOptions& opt = o.design;
  opt.seed = o.seed;
  opt.assess.fit.seed = o.seed;
  opt.assess.fit.threads = o.threads;
  opt.assess.fit.engine.dt_s = o.model.dt_s;
  if (o.orientations != 0) opt.assess.fit.alpha.marginal_points = o.orientations;
  opt.assess.fit.alpha.polish_points = o.polish_orientations;
  refuse_problems(opt.problems(), kDesignNames);
  // The box's rules (WideBox::problems) on the ranges given; the others are the set's own.
  refuse_problems(given_box.problems(),
                  {{"vin_x", "--range"}, {"vin_y", "--range"}, {"win", "--range"}});
  const Model model = o.model.build_model();
  const auto in = diagnosis::load_inputs(o.data, o.shape_given ? o.model.shape : "", o.where);
  diagnosis::WideBox box = diagnosis::box_of(in.set);
  if (given[kVx]) box.vin_x = given_box.vin_x;
  if (given[kVy]) box.vin_y = given_box.vin_y;
  if (given[kW]) box.win = given_box.win;
  const EffectRegistry& registry = EffectRegistry::global();
  std::vector<std::string> names = o.rivals;
  if (names.empty()) {
    diagnosis::DiagnoseOptions dopt;
    dopt.assess = opt.assess;
    dopt.progress = !o.output.json;
    names = diagnosis::default_rivals(model, in.shape, in.set, dopt);
    if (names.size() < 2)
      throw InputError("<command line>", 0, "--rivals",
                       "the diagnosis kept no law besides the base model: name the rivals "
                       "(e.g. --rivals none,rate_restitution)");
  }
  const auto rivals = diagnosis::parse_rivals(names, model, registry);
  const diagnosis::ThrowDesign d =
      diagnosis::design_throws(model, in.shape, in.set, rivals, box, opt);

  std::vector<std::string> rival_names;
  for (const auto& r : d.rivals) rival_names.push_back(r.name);
  const std::vector<std::string> comments = {
      "Ricochet impact set v1: incident states only (a plan of throws; docs/impact-sets.md, "
      "\"Incident states\")",
      fmt::format("ricochet {} design: {} throws deciding between the rivals {} "
                  "(T-optimal max-min, Atkinson & Fedorov 1975)",
                  kVersion, d.plan.size(), join(rival_names)),
      fmt::format("added to {} ({} releases of shape {}); box vin_x [{:g}, {:g}] m/s, vin_y "
                  "[{:g}, {:g}] m/s, win [{:g}, {:g}] rad/s; seed {}, {} candidates",
                  o.data, d.releases, d.shape, d.box.vin_x[0], d.box.vin_x[1], d.box.vin_y[0],
                  d.box.vin_y[1], d.box.win[0], d.box.win[1], d.seed, d.candidates),
      fmt::format(
          "weakest pair: noncentrality {:.4g} (power {:.3f} at level {:.3g}) with this plan, "
          "{:.4g} (power {:.3f}) with as many uniform throws",
          d.min_plan.lambda, d.min_plan.power, d.test_level, d.min_uniform.lambda,
          d.min_uniform.power)};
  write_plan_csv(d, o.output.out, comments);
  if (o.output.json) {
    nlohmann::json doc = diagnosis::to_json(d);
    doc["data"] = o.data;
    doc["out"] = o.output.out;
    print_json(doc);
    return;
  }
  print_text(d, o.data, o.output.out);
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto o = std::make_shared<DesignCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "design",
      "The throws that would decide between rival laws: a T-optimal max-min plan of new "
      "incident states (Atkinson & Fedorov 1975), written as an impact set of incident states");
  sub->add_option("SET", o->data, "Impact set the plan adds to (.csv, .h5)")->required();
  add_where_option(sub, o->where, "the releases of SET");
  add_model_options(sub, o->model);
  sub->add_option("--budget", o->design.budget, "New throws to plan")->capture_default_str();
  show_range(sub, "--budget", diagnosis::DesignOptions::kBudget);
  sub->add_option("--range", o->ranges,
                  "Box of the new incident states, NAME=A:B with NAME vin_x [m/s], vin_y [m/s] or "
                  "win [rad/s] (repeatable); a component not given spans SET's own range");
  sub->add_option("--rivals", o->rivals,
                  "Rival laws, comma-separated: none (the base model), a registered effect "
                  "(ricochet effects), or a+b; default: none plus the laws the diagnosis keeps")
      ->delimiter(',');
  sub->add_option("--candidates", o->design.candidates,
                  "Candidate states (Sobol' points in the box), at least the budget; 0: "
                  "max(1024, 4 x budget)")
      ->capture_default_str();
  show_range(sub, "--candidates", diagnosis::DesignOptions::kCandidates);
  sub->add_option("--alpha", o->design.alpha,
                  "Family-wise level of the discrimination tests (the predicted power: each pair "
                  "at alpha/(4 m(m-1)) for m rival laws other than none, two laws per family)")
      ->capture_default_str();
  show_range(sub, "--alpha", diagnosis::DesignOptions::kAlpha);
  sub->add_option("--passes", o->design.max_passes, "Exchange passes at most")
      ->capture_default_str();
  show_range(sub, "--passes", diagnosis::DesignOptions::kPasses);
  add_orientation_options(sub, o->orientations, o->polish_orientations);
  add_seed_option(sub, o->seed,
                  "every random draw: the uniform draw compared with the plan, the "
                  "calibrations' start designs, the cross-validation's partitions and the "
                  "score test's bootstrap of the diagnosis choosing the default rivals");
  add_threads_option(sub, o->threads);
  add_output_options(sub, o->output, JsonOut::kRefused);
  sub->get_option("--out")->required()->description(
      "The plan: an impact set of incident states (.csv)");
  sub->callback([o, sub] {
    o->shape_given = sub->get_option("--shape")->count() > 0;
    run(*o);
  });
}

}  // namespace ricochet::cli
