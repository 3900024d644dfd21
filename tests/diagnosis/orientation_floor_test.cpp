// The noise floor of a set whose block orientation is unknown counts the model's spread over
// that orientation, whatever the source of the measurement noise (issue 35, item 2): replicate
// releases with tiny declared uncertainties (a reconstructed LIGGGHTS campaign) used to get a
// floor of about their pooled within-group variance alone. A set with alpha_in uses its known
// orientation: no such term.
#include <gtest/gtest.h>

#include <string>

#include "diagnosis/assess.hpp"

namespace ricochet::diagnosis {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

// Six lab triangles, each thrown twice (one replicate label per pair) with outputs that differ
// by 0.1 mm/s, and tiny declared uncertainties: what a resolved campaign's replica beds give.
ImpactSet replicated_triangles(bool with_alpha) {
  ImpactSet lab = read_impact_set(kLab + "triangles.csv");
  ImpactSet set = lab;
  set.impacts.clear();
  for (std::size_t i = 0; i < 6; ++i)
    for (int r = 0; r < 2; ++r) {
      Impact im = lab.impacts[i];
      im.id += "_" + std::to_string(r);
      im.replicate = lab.impacts[i].id;
      im.vout[0] += 1e-4 * r;
      im.sigma_vin = Vel3{1e-3, 1e-3, 1e-2};
      im.sigma_vout = Vel3{1e-3, 1e-3, 1e-2};
      if (with_alpha) im.alpha_in = 0.2;
      set.impacts.push_back(im);
    }
  return set;
}

// The orientation term the floor must hold: mean over releases of sum_k spread_k^2 / d_k^2,
// the prediction's spread over the unknown orientation on the error's scale.
double orientation_term(const Model& model, const Shape& shape, const ImpactSet& set,
                        const std::array<bool, kObservables>& use, const AssessOptions& o) {
  const AssessOptions r = resolve_scale(set, o);
  const auto pred = predict_observables(model, shape, model.values(), set, r);
  double sum = 0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    const Obs d = error_scale(set.impacts[i], r);
    for (int k = 0; k < kObservables; ++k)
      if (use[k]) sum += pred[i].spread[k] * pred[i].spread[k] / (d[k] * d[k]);
  }
  return sum / static_cast<double>(set.size());
}

TEST(OrientationFloor, ReplicatesOfUnknownOrientationCountTheOrientationSpread) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const AssessOptions o;
  const ImpactSet set = replicated_triangles(false);
  const auto use = observables_of(set, o);
  const NoiseFloor f = noise_floor(model, shape, model.values(), set, use, o);
  EXPECT_EQ(f.source, "replicates");
  const double spread = orientation_term(model, shape, set, use, o);
  EXPECT_GT(spread, 0.01);  // a triangle's V_out depends on its orientation
  EXPECT_GE(f.value.mean, spread);
}

TEST(OrientationFloor, AKnownOrientationAddsNoSpread) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const AssessOptions o;
  const ImpactSet sampled = replicated_triangles(false), known = replicated_triangles(true);
  const auto use = observables_of(known, o);
  EXPECT_EQ(orientation_term(model, shape, known, use, o), 0.0);
  const NoiseFloor f = noise_floor(model, shape, model.values(), known, use, o);
  // Only the replicates' pooled scatter (0.1 mm/s on V_out^x): far below the sampled set's.
  EXPECT_LT(f.value.mean, 1e-3 * orientation_term(model, shape, sampled, use, o));
}

TEST(OrientationFloor, DeclaredUncertaintiesKeepTheOrientationSpread) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const AssessOptions o;
  // One release of each pair, unlabelled: no replicates (neither labels nor identical incident
  // states), so the declared uncertainties make the floor.
  const ImpactSet pairs = replicated_triangles(false);
  ImpactSet set = pairs;
  set.impacts.clear();
  for (std::size_t i = 0; i < pairs.size(); i += 2) {
    set.impacts.push_back(pairs.impacts[i]);
    set.impacts.back().replicate.reset();
  }
  const auto use = observables_of(set, o);
  const NoiseFloor f = noise_floor(model, shape, model.values(), set, use, o);
  EXPECT_EQ(f.source, "declared");
  // Twice the spread (neither the true nor the predicted orientation is known).
  EXPECT_GE(f.value.mean, 2.0 * orientation_term(model, shape, set, use, o));
}

}  // namespace
}  // namespace ricochet::diagnosis
