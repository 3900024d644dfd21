#include "diagnosis/synth.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "common/paths.hpp"
#include "fit/design.hpp"
#include "fit/fit.hpp"
#include "fit/lab_noise.hpp"

namespace ricochet::diagnosis {

NoiseSpec NoiseSpec::lab() {
  NoiseSpec s;
  s.vin = fit::LabNoise::vin;
  s.vout = fit::LabNoise::vout;
  s.penetration_m = fit::LabNoise::penetration_m;
  s.contact_duration_s = fit::LabNoise::contact_duration_s;
  return s;
}

NoiseSpec NoiseSpec::parse(const std::string& text, const std::string& option) {
  auto fail = [&](const std::string& why) {
    throw InputError("<command line>", 0, option, "'" + text + "': " + why);
  };
  NoiseSpec s;
  std::stringstream in(text);
  std::string item;
  bool first = true;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) fail("empty item");
    if (item == "lab" || item == "none" || item == "NONE") {
      if (!first) fail("'" + item + "' must come first");
      s = item == "lab" ? lab() : none();
      first = false;
      continue;
    }
    first = false;
    const auto eq = item.find('=');
    if (eq == std::string::npos) fail("expected NAME=SIGMA, got '" + item + "'");
    const std::string name = item.substr(0, eq);
    char* end = nullptr;
    const std::string num = item.substr(eq + 1);
    const double v = std::strtod(num.c_str(), &end);
    if (num.empty() || *end != '\0' || !std::isfinite(v)) fail("'" + num + "' is not a number");
    if (name == "vin_x")
      s.vin[kVx] = v;
    else if (name == "vin_y")
      s.vin[kVy] = v;
    else if (name == "win")
      s.vin[kW] = v;
    else if (name == "vout_x")
      s.vout[kVx] = v;
    else if (name == "vout_y")
      s.vout[kVy] = v;
    else if (name == "wout")
      s.vout[kW] = v;
    else if (name == "penetration")
      s.penetration_m = v;
    else if (name == "contact_duration")
      s.contact_duration_s = v;
    else if (name == "scale") {
      for (int k = 0; k < 3; ++k) s.vin[k] *= v, s.vout[k] *= v;
      s.penetration_m *= v;
      s.contact_duration_s *= v;
    } else {
      fail("unknown name '" + name +
           "' (known: vin_x, vin_y, win, vout_x, vout_y, wout, penetration, contact_duration, "
           "scale)");
    }
  }
  if (first) fail("empty noise specification");
  if (const OptionProblems p = s.problems(); !p.empty())
    fail(p.front().option + ": " + p.front().message);
  return s;
}

nlohmann::json NoiseSpec::to_json() const {
  return {{"vin", {vin[0], vin[1], vin[2]}},
          {"vout", {vout[0], vout[1], vout[2]}},
          {"penetration_m", penetration_m},
          {"contact_duration_s", contact_duration_s},
          {"units", "vin, vout: m/s, m/s, rad/s"}};
}

OptionProblems NoiseSpec::problems() const {
  OptionProblems p;
  for (double s : vin) check_range(p, "vin", s, kSigma);
  for (double s : vout) check_range(p, "vout", s, kSigma);
  check_range(p, "penetration_m", penetration_m, kSigma);
  check_range(p, "contact_duration_s", contact_duration_s, kSigma);
  return p;
}

OptionProblems WideBox::problems() const {
  OptionProblems p;
  // A range of one point is a component held fixed: a set's own span (box_of) can be one.
  const auto check = [&](const char* name, const std::array<double, 2>& r) {
    if (!(std::isfinite(r[0]) && std::isfinite(r[1]) && r[0] <= r[1]))
      p.push_back({name, fmt::format("{} [{:g}, {:g}] is empty: expected LO <= HI, both finite",
                                     name, r[0], r[1])});
  };
  check("vin_x", vin_x);
  check("vin_y", vin_y);
  check("win", win);
  if (!(vin_y[1] < 0))
    p.push_back({"vin_y", fmt::format("vin_y [{:g}, {:g}] reaches {:g}: it must stay below 0 (y "
                                      "is up: the block falls onto the ground)",
                                      vin_y[0], vin_y[1], vin_y[1])});
  return p;
}

OptionProblems SynthOptions::problems() const {
  OptionProblems p;
  check_range(p, "n", static_cast<double>(n), kN);
  append_nested(p, "noise", noise.problems());
  // The parameter's name is in the message: the field is the list.
  for (const auto& [name, sd] : scatter)
    if (!kSigma.contains(sd))
      p.push_back({"scatter", fmt::format("{}: value {} is outside {}", name, sd, kSigma.text())});
  check_range(p, "alpha_range_rad", alpha_range_rad[0], kAlphaRad);
  check_range(p, "alpha_range_rad", alpha_range_rad[1], kAlphaRad);
  if (!(alpha_range_rad[0] < alpha_range_rad[1]))
    p.push_back({"alpha_range_rad", "expected min < max"});
  append_nested(p, "wide", wide.problems());
  append_nested(p, "engine", engine.problems());
  return p;
}

const char* design_name(Design design) {
  return design == Design::kLab ? "lab" : "wide";
}

namespace {

// Columns of the uniform draw of one release (see synthesize()).
constexpr std::size_t kPick = 0;    // which measured state the lab design resamples
constexpr std::size_t kDesign = 1;  // 4 uniforms: 3 kernel normals (lab) or 3 box coordinates
constexpr std::size_t kAlpha = 5;   // orientation
constexpr std::size_t kNoise = 6;   // 8 uniforms: 8 normals (vin 3, vout 3, penetration, duration)
constexpr std::size_t kScatter = 14;  // 2 per scattered parameter (normals in pairs)

// Box-Muller: two standard normal deviates from two uniforms in [0, 1).
std::array<double, 2> box_muller(double u1, double u2) {
  const double r = std::sqrt(-2.0 * std::log(std::max(u1, 1e-300)));
  return {r * std::cos(2.0 * M_PI * u2), r * std::sin(2.0 * M_PI * u2)};
}

// Mixes the seed and the round so that rounds of redraws use independent streams.
std::uint64_t round_seed(std::uint64_t seed, std::uint64_t round) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (round + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return (z ^ (z >> 31)) & 0x7FFFFFFFULL;  // OpenTURNS seeds are 32-bit
}

}  // namespace

namespace {

// Silverman's bandwidth of the smoothed bootstrap of the lab design, per component (zero for the
// wide design, which does not resample).
Vel3 silverman_bandwidth(const SynthOptions& o) {
  Vel3 bandwidth{};
  if (o.design != Design::kLab) return bandwidth;
  const double m = static_cast<double>(o.incident.size());
  for (int k = 0; k < 3; ++k) {
    double mean = 0, sq = 0;
    for (const auto& im : o.incident.impacts) mean += im.vin[k] / m;
    for (const auto& im : o.incident.impacts) sq += (im.vin[k] - mean) * (im.vin[k] - mean);
    const double sd = m > 1 ? std::sqrt(sq / (m - 1)) : 0.0;
    bandwidth[k] = 1.06 * sd * std::pow(m, -0.2);
  }
  return bandwidth;
}

// The true incident state, orientation and parameter row of each draw of one round, from the
// uniform row r of that draw (the columns kPick ... kScatter).
void draw_cases(const Model& truth, const Shape& shape, const SynthOptions& o,
                const std::vector<double>& u, std::size_t dim, const Vel3& bandwidth,
                const std::vector<std::size_t>& scatter_index, std::vector<CollisionCase>& cases,
                std::vector<double>& params) {
  const std::size_t P = truth.parameter_count();
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const double* r = u.data() + i * dim;
    Vel3 vin{};
    if (o.design == Design::kLab) {
      const std::size_t pick =
          std::min(o.incident.size() - 1, static_cast<std::size_t>(r[kPick] * o.incident.size()));
      const auto z01 = box_muller(r[kDesign], r[kDesign + 1]);
      const auto z23 = box_muller(r[kDesign + 2], r[kDesign + 3]);
      const Vel3 z{z01[0], z01[1], z23[0]};
      for (int k = 0; k < 3; ++k) vin[k] = o.incident.impacts[pick].vin[k] + bandwidth[k] * z[k];
      // A kernel draw may leave the physical side: keep the block falling.
      vin[kVy] = std::min(vin[kVy], -0.05);
    } else {
      vin[kVx] = o.wide.vin_x[0] + (o.wide.vin_x[1] - o.wide.vin_x[0]) * r[kDesign];
      vin[kVy] = o.wide.vin_y[0] + (o.wide.vin_y[1] - o.wide.vin_y[0]) * r[kDesign + 1];
      vin[kW] = o.wide.win[0] + (o.wide.win[1] - o.wide.win[0]) * r[kDesign + 2];
    }
    cases[i].vin = vin;
    cases[i].alpha_rad =
        shape.is_disc()
            ? 0.0
            : o.alpha_range_rad[0] + (o.alpha_range_rad[1] - o.alpha_range_rad[0]) * r[kAlpha];
    std::copy(truth.values().begin(), truth.values().end(), params.begin() + i * P);
    for (std::size_t s = 0; s < scatter_index.size(); ++s) {
      const std::size_t j = scatter_index[s];
      const double z = box_muller(r[kScatter + 2 * s], r[kScatter + 2 * s + 1])[0];
      params[i * P + j] =
          std::clamp(truth.values()[j] + o.scatter[s].second * z, truth.lower(j), truth.upper(j));
    }
  }
}

// The measured release of draw i (true state plus measurement noise from the kNoise columns of
// r), or nothing when the truth did not rebound or the noise flips a sign; `truth_row` gets the
// true state for the truth file.
std::optional<Impact> measured_release(const SynthOptions& o, const Shape& shape, const double* r,
                                       const CollisionCase& cc, const CollisionResult& c,
                                       nlohmann::json& truth_row) {
  std::array<double, 8> z{};
  for (int p = 0; p < 4; ++p) {
    const auto zz = box_muller(r[kNoise + 2 * p], r[kNoise + 2 * p + 1]);
    z[2 * p] = zz[0];
    z[2 * p + 1] = zz[1];
  }
  Impact im;
  for (int k = 0; k < 3; ++k) {
    im.vin[k] = cc.vin[k] + o.noise.vin[k] * z[k];
    im.vout[k] = c.vout[k] + o.noise.vout[k] * z[3 + k];
  }
  if (c.status != CollisionStatus::kOk || !(im.vin[kVy] < 0) || !(im.vout[kVy] > 0))
    return std::nullopt;
  im.shape = shape.name;
  im.sigma_vin = o.noise.vin;
  im.sigma_vout = o.noise.vout;
  if (!shape.is_disc() && o.write_alpha) im.alpha_in = cc.alpha_rad;
  if (o.write_penetration) {
    im.penetration = std::max(0.0, c.max_penetration_m + o.noise.penetration_m * z[6]);
    im.extra.push_back(o.noise.penetration_m);
  }
  if (o.write_contact_duration) {
    im.contact_duration = std::max(0.0, c.contact_duration_s + o.noise.contact_duration_s * z[7]);
    im.extra.push_back(o.noise.contact_duration_s);
  }
  truth_row = {{"vin", {cc.vin[0], cc.vin[1], cc.vin[2]}},
               {"vout", {c.vout[0], c.vout[1], c.vout[2]}},
               {"alpha_rad", cc.alpha_rad},
               {"penetration_m", c.max_penetration_m},
               {"contact_duration_s", c.contact_duration_s}};
  return im;
}

std::vector<std::string> synth_comments(const SynthOptions& o, const Shape& shape, std::size_t size,
                                        std::size_t rejected) {
  const NoiseSpec& n = o.noise;
  return {
      "Ricochet impact set v1. Synthetic: `ricochet synth`, the reduced engine on drawn incident "
      "states with measurement noise.",
      fmt::format("{} releases of shape {}, seed {}, design {}, {} draws redrawn.", size,
                  shape.name, o.seed, design_name(o.design), rejected),
      fmt::format("Noise (1 sd): V_in {} m/s, {} m/s, {} rad/s; V_out {} m/s, {} m/s, {} rad/s; "
                  "penetration {} m; contact duration {} s.",
                  n.vin[0], n.vin[1], n.vin[2], n.vout[0], n.vout[1], n.vout[2], n.penetration_m,
                  n.contact_duration_s),
      "The truth model is not part of this file."};
}

}  // namespace

SynthResult synthesize(const Model& truth, const Shape& shape, const SynthOptions& o) {
  require_valid(o.problems(), "diagnosis::synthesize");
  if (o.design == Design::kLab && o.incident.empty())
    throw std::invalid_argument("synth: the lab design needs measured incident states");

  const std::size_t P = truth.parameter_count();
  std::vector<std::size_t> scatter_index;
  for (const auto& [name, sd] : o.scatter)
    scatter_index.push_back(truth.index(name));  // throws for an unknown name
  const std::size_t dim = kScatter + 2 * o.scatter.size();
  const Vel3 bandwidth = silverman_bandwidth(o);

  SynthResult out;
  ImpactSet& set = out.set;
  set.source = "ricochet synth";
  if (o.write_penetration) {
    set.extra_names.push_back(kSigmaPenetration);
    set.extra_units.push_back("m");
  }
  if (o.write_contact_duration) {
    set.extra_names.push_back(kSigmaContactDuration);
    set.extra_units.push_back("s");
  }
  nlohmann::json true_states = nlohmann::json::array();

  std::uint64_t round = 0;
  while (set.size() < o.n) {
    if (round > 1000)
      throw std::runtime_error(
          "synth: more than 1000 rounds of redraws; the truth model rarely "
          "rebounds on this design");
    const std::size_t need = o.n - set.size();
    // Draw a few extra per round so that a handful of rejections rarely costs another round.
    const std::size_t draws = need + need / 10 + 2;
    const std::vector<double> u = fit::uniform_unit_sample(dim, draws, round_seed(o.seed, round));
    ++round;

    std::vector<CollisionCase> cases(draws);
    std::vector<double> params(draws * P);
    draw_cases(truth, shape, o, u, dim, bandwidth, scatter_index, cases, params);
    const auto res = simulate_batch(truth, shape, cases, params, o.engine);

    for (std::size_t i = 0; i < draws && set.size() < o.n; ++i) {
      nlohmann::json row;
      std::optional<Impact> im =
          measured_release(o, shape, u.data() + i * dim, cases[i], res[i], row);
      if (!im) {
        ++out.rejected;
        continue;
      }
      im->id = fmt::format("{}{:03d}", o.id_prefix, set.size() + 1);
      nlohmann::json t = {{"id", im->id}};
      t.update(row);
      if (!scatter_index.empty()) {
        nlohmann::json p = nlohmann::json::object();
        for (std::size_t j : scatter_index) p[std::string(truth.spec(j).name)] = params[i * P + j];
        t["params"] = p;
      }
      true_states.push_back(std::move(t));
      set.impacts.push_back(std::move(*im));
    }
  }

  set.comments = synth_comments(o, shape, set.size(), out.rejected);
  nlohmann::json scatter = nlohmann::json::object();
  for (const auto& [name, sd] : o.scatter) scatter[name] = sd;
  out.truth = {{"model", truth.to_json()},
               {"shape", shape.name},
               {"n", o.n},
               {"seed", o.seed},
               {"design", design_name(o.design)},
               {"noise", o.noise.to_json()},
               {"scatter", scatter},
               {"rejected", out.rejected},
               {"releases", true_states}};
  validate(set);
  return out;
}

ImpactSet lab_incident_states(const Shape& shape) {
  const std::filesystem::path dir = data_dir();
  const std::string file = shape.name == "triangle" ? "triangles.csv" : "cylinders.csv";
  return read_impact_set((dir / "lab" / file).string());
}

}  // namespace ricochet::diagnosis
