// The throws that would decide between rival laws (throw_design.hpp).
#include "diagnosis/throw_design.hpp"
#include "common/nan.hpp"

#include <fmt/format.h>
#include <openturns/OT.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "common/clock.hpp"
#include "common/error.hpp"
#include "diagnosis/discrimination.hpp"
#include "diagnosis/encompassing.hpp"
#include "diagnosis/signature.hpp"
#include "fit/design.hpp"

namespace ricochet::diagnosis {

WideBox box_of(const ImpactSet& set) {
  WideBox b;
  if (set.empty()) return b;
  const auto span = [&](int k) {
    std::array<double, 2> r{set.impacts[0].vin[k], set.impacts[0].vin[k]};
    for (const auto& im : set.impacts) r = {std::min(r[0], im.vin[k]), std::max(r[1], im.vin[k])};
    return r;
  };
  b.vin_x = span(kVx);
  b.vin_y = span(kVy);
  b.win = span(kW);
  return b;
}

namespace {

using Clock = std::chrono::steady_clock;

// A point of the unit cube mapped into the box.
Vel3 in_box(const WideBox& b, double u0, double u1, double u2) {
  return {b.vin_x[0] + u0 * (b.vin_x[1] - b.vin_x[0]), b.vin_y[0] + u1 * (b.vin_y[1] - b.vin_y[0]),
          b.win[0] + u2 * (b.win[1] - b.win[0])};
}

// K points of the Sobol' sequence in the box (OpenTURNS; deterministic: no seed).
std::vector<Vel3> sobol_states(const WideBox& box, std::size_t k) {
  const OT::Sample s = OT::SobolSequence(3).generate(k);
  std::vector<Vel3> out(k);
  for (std::size_t i = 0; i < k; ++i) out[i] = in_box(box, s(i, 0), s(i, 1), s(i, 2));
  return out;
}

// n states drawn uniformly in the box (OpenTURNS' generator, seeded: fit::uniform_unit_sample).
std::vector<Vel3> uniform_states(const WideBox& box, std::size_t n, std::uint64_t seed) {
  const std::vector<double> u = fit::uniform_unit_sample(3, n, seed);
  std::vector<Vel3> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = in_box(box, u[3 * i], u[3 * i + 1], u[3 * i + 2]);
  return out;
}

Impact state_impact(const std::string& id, const std::string& shape, const Vel3& vin) {
  Impact im;
  im.id = id;
  im.shape = shape;
  im.vin = vin;
  im.vout = {kNaN, kNaN, kNaN};  // not thrown yet
  return im;
}

// A rival's predictions on the states and the forward-difference columns of its calibrated
// parameters (probe_calibrated: the diagnosis's steps, 2 % of a range or of a log range).
struct RivalPredictions {
  std::vector<ObsPrediction> value;
  std::vector<ParameterProbe> probes;
};

RivalPredictions predict_rival(const Rival& r, const Shape& shape, const ImpactSet& states,
                               const AssessOptions& o) {
  RivalPredictions p;
  p.value = predict_observables(r.model, shape, r.model.values(), states, o);
  p.probes = probe_calibrated(r.model, shape, states, o);
  return p;
}

bool subset_of(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  return std::all_of(a.begin(), a.end(), [&](const std::string& e) {
    return std::find(b.begin(), b.end(), e) != b.end();
  });
}

}  // namespace

OptionProblems DesignOptions::problems() const {
  OptionProblems p;
  check_range(p, "budget", static_cast<double>(budget), kBudget);
  check_range(p, "candidates", static_cast<double>(candidates), kCandidates);
  if (candidates > 0 && candidates < budget)
    p.push_back({"candidates", fmt::format("{} candidates cannot hold a budget of {} throws: give "
                                           "at least the budget, or 0 (the default: max(1024, "
                                           "4 x budget))",
                                           candidates, budget)});
  check_range(p, "alpha", alpha, kAlpha);
  check_range(p, "max_passes", static_cast<double>(max_passes), kPasses);
  check_range(p, "indistinguishable_lambda", indistinguishable_lambda, kIndistinguishable);
  check_range(p, "budget_power", budget_power, kPower);
  append_nested(p, "assess", assess.problems());
  return p;
}

namespace {

// What the phases of design_throws share: the states (the set's, the K candidates, the uniform
// draw), which of them inform, their error denominators, the layout of the Direction arrays
// ([set][kept candidates][uniform]), every ordered pair's direction and every pair's rule.
struct Workspace {
  std::size_t n = 0, K = 0, budget = 0;
  ImpactSet states;
  std::map<std::string, RivalPredictions> cache;  ///< predictions by rival name
  std::vector<char> ok;
  std::vector<Obs> scale;
  std::vector<std::size_t> kept, layout;
  std::vector<Direction> directions;
  std::vector<std::vector<std::size_t>> dir_of;  ///< [truth][fitted] -> index in directions
  std::vector<PairRule> rules;                   ///< aligned with ThrowDesign::pairs

  const RivalPredictions& predictions_of(const Rival& r, const Shape& shape,
                                         const AssessOptions& o) {
    auto it = cache.find(r.name);
    if (it == cache.end()) it = cache.emplace(r.name, predict_rival(r, shape, states, o)).first;
    return it->second;
  }
  std::vector<std::size_t> set_states() const {
    std::vector<std::size_t> s(n);
    for (std::size_t i = 0; i < n; ++i) s[i] = i;
    return s;
  }
};

// The states: the set's, then the K candidates (a low-discrepancy sequence over the box), then
// the uniform draw of the budget (the comparison design).
void add_states(Workspace& w, ThrowDesign& d, const ImpactSet& set, const Shape& shape,
                const WideBox& box, std::uint64_t seed) {
  const std::vector<Vel3> cand = sobol_states(box, w.K);
  d.uniform = uniform_states(box, w.budget, seed);
  w.states = set;
  for (std::size_t i = 0; i < w.K; ++i)
    w.states.impacts.push_back(state_impact(fmt::format("K{:05d}", i + 1), shape.name, cand[i]));
  for (std::size_t i = 0; i < w.budget; ++i)
    w.states.impacts.push_back(
        state_impact(fmt::format("U{:05d}", i + 1), shape.name, d.uniform[i]));
}

// Which states inform (every rival and every probe rebounds there), their error denominators
// (measured V_out for the set, the base model's prediction for a state not thrown yet), the
// candidates kept, and the layout. Throws InputError naming --range when fewer candidates than
// the budget inform.
void screen_states(Workspace& w, ThrowDesign& d, const std::vector<ObsPrediction>& base_pred,
                   const std::vector<const RivalPredictions*>& pred, const AssessOptions& o) {
  const std::size_t S = w.states.size(), n = w.n;
  w.ok.assign(S, 1);
  for (const RivalPredictions* p : pred)
    for (std::size_t s = 0; s < S; ++s) {
      w.ok[s] = w.ok[s] && p->value[s].status == CollisionStatus::kOk;
      for (const ParameterProbe& q : p->probes)
        w.ok[s] = w.ok[s] && q.predictions[s].status == CollisionStatus::kOk;
    }
  w.scale.resize(S);
  for (std::size_t s = 0; s < S; ++s) {
    Impact im = w.states.impacts[s];
    if (s >= n) {
      const Obs& b = base_pred[s].value;
      im.vout = {b[kObsVx], b[kObsVy], b[kObsW]};
      im.penetration = b[kObsPenetration];
      im.contact_duration = b[kObsDuration];
    }
    w.scale[s] = error_scale(im, o);
  }
  for (std::size_t i = 0; i < w.K; ++i)
    if (w.ok[n + i]) w.kept.push_back(n + i);
  d.excluded = w.K - w.kept.size();
  if (w.kept.size() < w.budget)
    throw InputError("<command line>", 0, "--range",
                     fmt::format("only {} of the {} candidate states rebound under every rival: "
                                 "widen the box (faster or steeper throws) or lower --budget",
                                 w.kept.size(), w.K));
  for (std::size_t s = 0; s < n; ++s) w.layout.push_back(s);
  w.layout.insert(w.layout.end(), w.kept.begin(), w.kept.end());
  for (std::size_t i = 0; i < w.budget; ++i) w.layout.push_back(n + w.K + i);
}

// The per-state terms of every ordered pair (truth a, refitted b), whitened by W, on the
// observables `obs`.
void build_directions(Workspace& w, const std::vector<const RivalPredictions*>& pred,
                      const std::vector<int>& obs, const Eigen::MatrixXd& W) {
  const std::size_t R = pred.size();
  const auto kobs = static_cast<Eigen::Index>(obs.size());
  w.dir_of.assign(R, std::vector<std::size_t>(R, 0));
  for (std::size_t ia = 0; ia < R; ++ia)
    for (std::size_t ib = 0; ib < R; ++ib) {
      if (ia == ib) continue;
      const RivalPredictions& pa = *pred[ia];
      const RivalPredictions& pb = *pred[ib];
      Direction dir;
      dir.truth = ia;
      dir.fitted = ib;
      dir.parameters = static_cast<int>(pb.probes.size());
      dir.states.reserve(w.layout.size());
      for (std::size_t s : w.layout) {
        Eigen::VectorXd r = Eigen::VectorXd::Zero(kobs);
        Eigen::MatrixXd G = Eigen::MatrixXd::Zero(kobs, dir.parameters);
        if (w.ok[s])
          for (Eigen::Index row = 0; row < kobs; ++row) {
            const int k = obs[static_cast<std::size_t>(row)];
            r[row] = (pa.value[s].value[k] - pb.value[s].value[k]) / w.scale[s][k];
            for (int c = 0; c < dir.parameters; ++c) {
              const ParameterProbe& q = pb.probes[static_cast<std::size_t>(c)];
              G(row, c) =
                  (q.predictions[s].value[k] - pb.value[s].value[k]) / q.step / w.scale[s][k];
            }
          }
        if (!r.allFinite() || !G.allFinite()) r.setZero(), G.setZero();
        dir.states.push_back(state_terms(W * r, W * G));
      }
      w.dir_of[ia][ib] = w.directions.size();
      w.directions.push_back(std::move(dir));
    }
}

// One pair on one design: the noncentrality of each direction, the rule's, and its power.
PairOnDesign on_design(const Workspace& w, const PairResult& p, const PairRule& rule,
                       const std::vector<std::size_t>& design, double test_level) {
  PairOnDesign r;
  r.lambda_ab = direction_lambda(w.directions[w.dir_of[p.a][p.b]], design);
  r.lambda_ba = direction_lambda(w.directions[w.dir_of[p.b][p.a]], design);
  r.lambda = std::numeric_limits<double>::infinity();
  for (std::size_t di : rule.directions)
    r.lambda = std::min(r.lambda, di == w.dir_of[p.a][p.b] ? r.lambda_ab : r.lambda_ba);
  r.power = discrimination_power(r.lambda, test_level);
  return r;
}

// Pairs: their rules (a nested pair is tested in one direction, the larger law true), which
// ones no throw could decide, and which ones the budget cannot (each decidable pair's own
// greedy plan, file comment). Returns the rules the plan must serve.
std::vector<PairRule> classify_pairs(Workspace& w, ThrowDesign& d, const DesignOptions& options,
                                     const SelectionOptions& greedy_only) {
  const std::size_t R = d.rivals.size(), n = w.n;
  std::vector<std::size_t> all_states(n + w.kept.size());
  for (std::size_t s = 0; s < all_states.size(); ++s) all_states[s] = s;
  for (std::size_t ia = 0; ia < R; ++ia)
    for (std::size_t ib = ia + 1; ib < R; ++ib) {
      PairResult p;
      p.a = ia;
      p.b = ib;
      PairRule rule;
      const auto& ea = d.rivals[ia].effects;
      const auto& eb = d.rivals[ib].effects;
      if (ea.size() < eb.size() && subset_of(ea, eb)) {
        p.nested = true;  // b is the larger law: b true, a refitted
        rule.directions = {w.dir_of[ib][ia]};
      } else if (eb.size() < ea.size() && subset_of(eb, ea)) {
        p.nested = true;
        rule.directions = {w.dir_of[ia][ib]};
      } else {
        rule.directions = {w.dir_of[ia][ib], w.dir_of[ib][ia]};
      }
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t di : rule.directions)
        best = std::min(best, direction_lambda(w.directions[di], all_states));
      p.indistinguishable = !(best >= options.indistinguishable_lambda);
      w.rules.push_back(rule);
      d.pairs.push_back(p);
    }
  std::vector<PairRule> active;
  for (std::size_t k = 0; k < d.pairs.size(); ++k) {
    PairResult& p = d.pairs[k];
    if (p.indistinguishable) continue;
    std::vector<std::size_t> alone = w.set_states();
    for (std::size_t c :
         select_max_min(w.directions, {w.rules[k]}, n, w.kept.size(), greedy_only).chosen)
      alone.push_back(c);
    p.alone = on_design(w, p, w.rules[k], alone, d.test_level);
    p.beyond_budget = !(p.alone.power >= options.budget_power);
    if (!p.beyond_budget) active.push_back(w.rules[k]);
  }
  return active;
}

// The plan: the max-min selection for the active pairs, or, with nothing to decide, the first
// candidates of the low-discrepancy sequence (space filling). Returns the chosen layout indices.
std::vector<std::size_t> choose_plan(const Workspace& w, ThrowDesign& d,
                                     const std::vector<PairRule>& active,
                                     const SelectionOptions& so) {
  std::vector<std::size_t> chosen;
  if (!active.empty()) {
    const Selection sel = select_max_min(w.directions, active, w.n, w.kept.size(), so);
    chosen = sel.chosen;
    d.greedy_lambda = sel.greedy_value;
    d.passes = sel.passes;
    d.swaps = sel.swaps;
  } else {
    for (std::size_t i = 0; i < w.budget; ++i) chosen.push_back(w.n + i);
    d.greedy_lambda = kNaN;
  }
  for (std::size_t c : chosen) d.plan.push_back(w.states.impacts[w.layout[c]].vin);
  return chosen;
}

// Every pair on the three designs (the set alone, the set with the plan, the set with the
// uniform draw), and the weakest decidable pair on each.
void judge_designs(const Workspace& w, ThrowDesign& d, const std::vector<std::size_t>& chosen) {
  const std::vector<std::size_t> set_states = w.set_states();
  std::vector<std::size_t> plan_states = set_states, uniform_design = set_states;
  plan_states.insert(plan_states.end(), chosen.begin(), chosen.end());
  for (std::size_t i = 0; i < w.budget; ++i) uniform_design.push_back(w.n + w.kept.size() + i);
  const auto min_into = [](PairOnDesign& m, const PairOnDesign& x, bool first) {
    if (first || x.lambda < m.lambda) m = x;
  };
  bool first = true;
  for (std::size_t k = 0; k < d.pairs.size(); ++k) {
    PairResult& p = d.pairs[k];
    p.plan = on_design(w, p, w.rules[k], plan_states, d.test_level);
    p.uniform = on_design(w, p, w.rules[k], uniform_design, d.test_level);
    p.set = on_design(w, p, w.rules[k], set_states, d.test_level);
    if (p.indistinguishable || p.beyond_budget) continue;
    min_into(d.min_plan, p.plan, first);
    min_into(d.min_uniform, p.uniform, first);
    min_into(d.min_set, p.set, first);
    first = false;
  }
  if (first)
    for (PairOnDesign* m : {&d.min_plan, &d.min_uniform, &d.min_set}) *m = {kNaN, kNaN, kNaN, kNaN};
}

}  // namespace

ThrowDesign design_throws(const Model& base, const Shape& shape, const ImpactSet& set,
                          const std::vector<std::vector<std::string>>& rival_effects,
                          const WideBox& box, const DesignOptions& options) {
  require_valid(options.problems(), "diagnosis::design_throws");
  OptionProblems box_problems;
  append_nested(box_problems, "box", box.problems());
  require_valid(box_problems, "diagnosis::design_throws");
  const auto t0 = Clock::now();
  const EffectRegistry& registry = options.registry ? *options.registry : EffectRegistry::global();
  const AssessOptions o = resolve_scale(set, options.assess);
  Workspace w;
  w.n = set.size();
  w.budget = options.budget;
  w.K = options.candidates > 0 ? options.candidates : std::max<std::size_t>(1024, 4 * w.budget);
  if (rival_effects.size() < 2) throw std::invalid_argument("design_throws: two rivals at least");

  ThrowDesign d;
  d.shape = shape.name;
  d.box = box;
  d.releases = w.n;
  d.candidates = w.K;
  d.alpha = options.alpha;
  d.seed = options.seed;

  // 1. The rivals, calibrated on the set; the base model's fit gives the noise's whitening.
  std::vector<Rival> all = calibrate_rivals(base, shape, set, rival_effects, o, registry);
  const Rival base_fit = all.front();
  d.rivals.assign(all.begin() + 1, all.end());
  // The level the diagnosis's second stage tests each ordered pair of families at (ThrowDesign).
  const auto m = static_cast<double>(std::count_if(
      d.rivals.begin(), d.rivals.end(), [](const Rival& r) { return !r.effects.empty(); }));
  const double r = static_cast<double>(detail::kFamilyRepresentatives);
  d.test_level = m >= 2 ? options.alpha / (r * r * m * (m - 1)) : options.alpha;
  d.calibration_s = seconds_since(t0);
  const auto t1 = Clock::now();
  Assessment a;
  a.use = observables_of(set, o);
  a.population = base_fit.fit;
  a.insample_predictions = to_observables(base_fit.fit.predictions);
  a.insample = error_report(set, a.insample_predictions, a.use, o);
  const detail::Directions noise = detail::base_directions(base_fit.model, shape, set, a, o);
  d.use = a.use;
  std::vector<int> obs;
  for (int k = 0; k < kObservables; ++k)
    if (a.use[k]) obs.push_back(k);

  // 2. The states and their predictions, one engine batch per parameter vector; the base
  // model's ("none") once.
  add_states(w, d, set, shape, box, options.seed);
  const std::vector<ObsPrediction>& base_pred = w.predictions_of(base_fit, shape, o).value;
  std::vector<const RivalPredictions*> pred;
  for (const Rival& rival : d.rivals) pred.push_back(&w.predictions_of(rival, shape, o));
  screen_states(w, d, base_pred, pred, o);
  // 3. The per-state terms of every ordered pair.
  build_directions(w, pred, obs, noise.whiten);
  d.prediction_s = seconds_since(t1);
  const auto t2 = Clock::now();

  // 4. Pairs; 5. the plan; 6. every pair on the three designs.
  SelectionOptions so;
  so.budget = w.budget;
  so.max_passes = options.max_passes;
  SelectionOptions greedy_only = so;
  greedy_only.max_passes = 0;
  const std::vector<PairRule> active = classify_pairs(w, d, options, greedy_only);
  const std::vector<std::size_t> chosen = choose_plan(w, d, active, so);
  d.selection_s = seconds_since(t2);
  judge_designs(w, d, chosen);
  d.seconds = seconds_since(t0);
  return d;
}

}  // namespace ricochet::diagnosis
