// The force histories as a calibration target (diagnosis/history_objective.hpp) and the fit's
// hook that carries it (fit::FitOptions::extra_objective). The "measured" histories here are the
// law's own force along the engine's own trajectories at known parameters, so the term's value
// is known exactly there (0) and its scaling by the weight and the floors can be checked by
// hand; what the term does on data the engine did not make is measured in docs/diagnosis.md.
#include "diagnosis/history_objective.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "engine/path_force.hpp"
#include "fit/fit.hpp"

namespace ricochet::diagnosis {
namespace {

// Two releases of the lab cylinder at the paper's law with `en2`, their histories the law's
// force along the engine's trace (moment about the centre of mass, as a track's torque).
struct Case {
  ImpactSet set;
  std::vector<std::optional<MeasuredHistory>> histories;
};

Case two_releases(double en2) {
  const Model m = Model::paper();
  std::vector<double> p = m.values();
  p[m.index("en2")] = en2;
  const Shape shape = Shape::cylinder();
  Case c;
  const std::array<CollisionCase, 2> states = {CollisionCase{{2.9, -2.3, -65.0}, 0.0},
                                               CollisionCase{{4.0, -3.0, -30.0}, 0.0}};
  for (std::size_t i = 0; i < states.size(); ++i) {
    Trace tr;
    const CollisionResult r = simulate(m, shape, states[i], p, {}, &tr);
    Impact im;
    im.id = "R" + std::to_string(i);
    im.shape = "cylinder";
    im.vin = states[i].vin;
    im.vout = r.vout;
    c.set.impacts.push_back(im);
    MeasuredHistory h;
    h.id = im.id;
    for (std::size_t k = 0; k < tr.t.size(); ++k)
      h.path.push_back({tr.t[k], tr.x[k], tr.y[k], tr.theta[k], tr.vx[k], tr.vy[k], tr.w[k]});
    for (const PathForce& f : law_force_along(m, shape, h.path, p)) {
      h.fx_N.push_back(f.fx_N);
      h.fy_N.push_back(f.fy_N);
      h.torque_Nm.push_back(f.torque_Nm);
    }
    c.histories.push_back(h);
  }
  return c;
}

TEST(HistoryObjective, IsZeroAtTheHistoriesOwnLawAndScalesWithWeightAndFloor) {
  const Case c = two_releases(0.15);
  const Model m = Model::paper();
  const std::array<double, kForceComponents> floor = {100.0, 50.0, 5.0};
  const auto o = history_objective(c.set, c.histories, floor, 0.03, Shape::cylinder(), {}, "--w");
  std::vector<double> p = m.values();
  p[m.index("en2")] = 0.15;
  EXPECT_EQ((*o)(m, p, c.set), 0.0);
  p[m.index("en2")] = 0.05;  // a softer unloading: the force after the peak differs
  const double off = (*o)(m, p, c.set);
  EXPECT_GT(off, 0.0);
  // Linear in the weight; a floor twice as large on every component quarters it.
  const auto o2 = history_objective(c.set, c.histories, floor, 0.06, Shape::cylinder(), {}, "--w");
  EXPECT_NEAR((*o2)(m, p, c.set), 2 * off, 1e-12 * off);
  const std::array<double, kForceComponents> wide = {200.0, 100.0, 10.0};
  const auto o3 = history_objective(c.set, c.histories, wide, 0.03, Shape::cylinder(), {}, "--w");
  EXPECT_NEAR((*o3)(m, p, c.set), off / 4, 1e-12 * off);
  // Only the releases being fitted count: a fold of one release sees its own history alone.
  ImpactSet first = c.set;
  first.impacts.resize(1);
  const double part = (*o)(m, p, first);
  EXPECT_GT(part, 0.0);
  EXPECT_LT(part, off);
}

TEST(HistoryObjective, RefusesAWeightOrAFloorItCannotUse) {
  const Case c = two_releases(0.15);
  const std::array<double, kForceComponents> floor = {100.0, 50.0, 5.0};
  for (const double w : {0.0, -1.0, std::nan("")}) {
    try {
      (void)history_objective(c.set, c.histories, floor, w, Shape::cylinder(), {}, "--w");
      ADD_FAILURE() << "accepted weight " << w;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--w");
    }
  }
  try {
    (void)history_objective(c.set, c.histories, {NAN, NAN, NAN}, 0.03, Shape::cylinder(), {},
                            "--w");
    ADD_FAILURE() << "accepted a floor without a component";
  } catch (const InputError& e) {
    EXPECT_NE(e.detail().find("replicate floor"), std::string::npos) << e.what();
  }
}

// The fit's hook: a population fit minimises Eq. 7 plus the term. A steep term around mu = 0.9
// (far from where the lab cylinders' rebounds put mu) moves the fit there; without it the fit
// stays where Eq. 7 alone puts it.
TEST(HistoryObjective, APopulationFitMinimisesTheAddedTerm) {
  const ImpactSet lab =
      read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/cylinders.csv");
  const Model m = Model::paper();
  fit::FitOptions o;
  o.intervals = false;
  const double alone =
      fit::calibrate_population(m, Shape::cylinder(), lab, o).params[m.index("mu")];
  o.extra_objective = [&m](const Model& model, std::span<const double> p, const ImpactSet& s) {
    EXPECT_EQ(model.parameter_count(), m.parameter_count());
    EXPECT_EQ(s.size(), 28u);
    const double d = p[model.index("mu")] - 0.9;
    return 1e4 * d * d;
  };
  const fit::PopulationFit pulled = fit::calibrate_population(m, Shape::cylinder(), lab, o);
  EXPECT_GT(std::abs(alone - 0.9), 0.2) << "Eq. 7 alone puts mu at " << alone;
  EXPECT_NEAR(pulled.params[m.index("mu")], 0.9, 0.02);
}

}  // namespace
}  // namespace ricochet::diagnosis
