// `ricochet synth --model FILE --n N --seed K --out DATA`: a synthetic impact set from a truth
// model, with incident states drawn like the lab's and lab-like measurement noise
// (docs/commands/synth.md). The truth model is written only to the separate --truth file.
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "common/error.hpp"
#include "diagnosis/synth.hpp"
#include "model_options.hpp"
#include "shared_options.hpp"

namespace ricochet::cli {
namespace {

struct SynthCliOptions {
  ModelOptions model;
  OutputOptions output;
  /// --n, --seed and --threads write into synth: their defaults are the diagnosis module's.
  diagnosis::SynthOptions synth;
  std::string where;
  std::string design = "lab";
  std::string noise = "lab";
  std::string incident;
  std::vector<std::string> scatter;
  std::string features = "alpha_in,penetration,contact_duration";
  std::string truth;
  std::vector<std::string> box;
};

// --box NAME=LO:HI (repeatable), NAME in vin_x, vin_y, win. The box's rules (LO <= HI, vin_y
// below 0) are WideBox::problems()'s, refused with the other options.
void parse_box(const std::vector<std::string>& items, diagnosis::WideBox& box) {
  for (const auto& item : items) {
    const auto eq = item.find('='), colon = item.find(':');
    auto fail = [&](const std::string& why) {
      throw InputError("<command line>", 0, "--box", "'" + item + "': " + why);
    };
    if (eq == std::string::npos || colon == std::string::npos || colon < eq)
      fail("expected NAME=LO:HI, e.g. vin_x=3:6");
    const std::string name = item.substr(0, eq);
    char* e1 = nullptr;
    char* e2 = nullptr;
    const std::string a = item.substr(eq + 1, colon - eq - 1), b = item.substr(colon + 1);
    const double lo = std::strtod(a.c_str(), &e1), hi = std::strtod(b.c_str(), &e2);
    if (a.empty() || b.empty() || *e1 != '\0' || *e2 != '\0') fail("LO and HI must be numbers");
    if (name == "vin_x")
      box.vin_x = {lo, hi};
    else if (name == "vin_y")
      box.vin_y = {lo, hi};
    else if (name == "win")
      box.win = {lo, hi};
    else
      fail("unknown name '" + name + "' (known: vin_x, vin_y, win)");
  }
}

void parse_features(const std::string& text, diagnosis::SynthOptions& s) {
  s.write_alpha = s.write_penetration = s.write_contact_duration = false;
  if (text == "none") return;
  std::stringstream in(text);
  std::string f;
  while (std::getline(in, f, ',')) {
    if (f == "alpha_in")
      s.write_alpha = true;
    else if (f == "penetration")
      s.write_penetration = true;
    else if (f == "contact_duration")
      s.write_contact_duration = true;
    else
      throw InputError(
          "<command line>", 0, "--features",
          "unknown feature '" + f + "' (known: alpha_in, penetration, contact_duration, or none)");
  }
}

// The command line's names of the synth options it binds (their ranges: SynthOptions::problems).
const OptionNames kSynthNames = {{"n", "--n"},
                                 {"scatter", "--scatter"},
                                 {"noise.vin", "--noise"},
                                 {"noise.vout", "--noise"},
                                 {"noise.penetration_m", "--noise"},
                                 {"noise.contact_duration_s", "--noise"},
                                 {"wide.vin_x", "--box"},
                                 {"wide.vin_y", "--box"},
                                 {"wide.win", "--box"},
                                 {"engine.dt_s", "--dt"}};

void run(const SynthCliOptions& o) {
  require_extension("--out", o.output.out, {".csv", ".h5", ".hdf5"});
  if (!o.truth.empty()) require_extension("--truth", o.truth, {".json"});
  const Model truth = o.model.build_model();
  const Shape shape = o.model.build_shape();
  diagnosis::SynthOptions s = o.synth;
  if (o.design == "lab")
    s.design = diagnosis::Design::kLab;
  else if (o.design == "wide")
    s.design = diagnosis::Design::kWide;
  else
    throw InputError("<command line>", 0, "--design", "'" + o.design + "': use lab or wide");
  s.noise = diagnosis::NoiseSpec::parse(o.noise, "--noise");
  for (const auto& item : o.scatter) {
    const auto eq = item.find('=');
    char* end = nullptr;
    const std::string num = eq == std::string::npos ? "" : item.substr(eq + 1);
    const double sd = std::strtod(num.c_str(), &end);
    if (eq == std::string::npos || num.empty() || *end != '\0')
      throw InputError("<command line>", 0, "--scatter", "'" + item + "': expected NAME=SD");
    const std::string name = item.substr(0, eq);
    try {
      (void)truth.index(name);
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "--scatter", e.what());
    }
    s.scatter.emplace_back(name, sd);
  }
  parse_features(o.features, s);
  parse_box(o.box, s.wide);
  if (!o.box.empty() && s.design != diagnosis::Design::kWide)
    throw InputError("<command line>", 0, "--box", "the box applies to --design wide only");
  s.engine.dt_s = o.model.engine_options().dt_s;
  refuse_problems(s.problems(), kSynthNames);
  // The measured states are read once the options are known to be valid.
  if (s.design == diagnosis::Design::kLab)
    s.incident = o.incident.empty()
                     ? diagnosis::lab_incident_states(shape)
                     : filter_nonempty(read_impact_set(o.incident), o.where, o.incident);

  const diagnosis::SynthResult r = diagnosis::synthesize(truth, shape, s);
  write_impact_set(r.set, o.output.out);
  if (!o.truth.empty()) write_text_file(o.truth, stamp_json(r.truth).dump(2) + "\n", "--truth");
  if (o.output.json) {
    print_json(
        {{"out", o.output.out},
         {"n", r.set.size()},
         {"rejected", r.rejected},
         {"seed", s.seed},
         {"design", o.design},
         {"shape", shape.name},
         {"noise", s.noise.to_json()},
         {"truth_file", o.truth.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.truth)}});
    return;
  }
  std::cout << "wrote " << r.set.size() << " releases to " << o.output.out << " (" << r.rejected
            << " draws redrawn)";
  if (!o.truth.empty()) std::cout << "; truth model in " << o.truth;
  std::cout << "\n";
}

}  // namespace

void add_synth_command(CLI::App& app) {
  auto o = std::make_shared<SynthCliOptions>();
  CLI::App* sub = app.add_subcommand(
      "synth",
      "Synthetic impact set from a truth model (engine + effects + parameters): incident states "
      "like the lab's or a wide design, lab-like measurement noise. The truth is not written "
      "into the data");
  add_model_options(sub, o->model);
  sub->add_option("--n", o->synth.n, "Number of releases")->capture_default_str();
  show_range(sub, "--n", diagnosis::SynthOptions::kN);
  add_seed_option(sub, o->synth.seed, "every random draw");
  sub->add_option("--design", o->design,
                  "lab: resample and perturb measured incident states; wide: uniform over "
                  "V_in^x 1.5..6 m/s, V_in^y -5..-1 m/s, omega_in -90..0 rad/s")
      ->capture_default_str();
  sub->add_option("--noise", o->noise,
                  "lab | none | list such as lab,contact_duration=2e-4 (SI standard deviations "
                  "of vin_x, vin_y, win, vout_x, vout_y, wout, penetration, contact_duration; "
                  "scale=F multiplies)")
      ->capture_default_str();
  sub->add_option("--box", o->box,
                  "Wide design range, NAME=LO:HI with NAME in vin_x, vin_y, win (SI; "
                  "repeatable)");
  sub->add_option("--incident", o->incident,
                  "Impact set whose incident states the lab design resamples (default: the lab "
                  "data of the shape)");
  add_where_option(sub, o->where, "the releases of --incident");
  sub->add_option("--scatter", o->scatter,
                  "Per-release scatter of a truth parameter, NAME=SD with SD in " +
                      diagnosis::SynthOptions::kSigma.text() + " (repeatable)");
  sub->add_option("--features", o->features,
                  "Features written: any of alpha_in,penetration,contact_duration, or none (as "
                  "the paper's lab data)")
      ->capture_default_str();
  sub->add_option("--truth", o->truth,
                  "Also write the truth (model, options, true states) to this JSON file");
  add_threads_option(sub, o->synth.engine.threads);
  add_output_options(sub, o->output, JsonOut::kRefused);
  sub->get_option("--out")->required();
  sub->callback([o] { run(*o); });
}

}  // namespace ricochet::cli
