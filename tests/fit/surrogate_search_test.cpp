// The response-surface search of orientation-averaged population fits (fit/surrogate_search.hpp)
// and the collision memo the fits of one assessment share (fit/collision_memo.hpp): the
// interpolant against functions it must reproduce, the search against test functions with
// known minima (Branin's three, Dixon & Szego 1978, the standard set of Gutmann 2001 and Regis
// & Shoemaker 2005), and the memo against the engine run directly and through the multi-start's
// shared first points.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>

#include "fit/collision_memo.hpp"
#include "fit/design.hpp"
#include "fit/fibers.hpp"
#include "fit/fit.hpp"
#include "fit/optimize.hpp"
#include "fit/surrogate_search.hpp"

namespace ricochet::fit {
namespace {

using detail::CubicRbf;
using detail::LocalResult;

class FunctionProblem final : public detail::Problem {
 public:
  FunctionProblem(std::size_t dim, std::function<double(const std::vector<double>&)> f)
      : dim_(dim), f_(std::move(f)) {}
  std::size_t dim() const override { return dim_; }
  double eval(const std::vector<double>& u) override {
    ++evaluations;
    return f_(u);
  }

 private:
  std::size_t dim_;
  std::function<double(const std::vector<double>&)> f_;
};

TEST(CubicRbf, InterpolatesItsNodesAndReproducesALinearFunction) {
  const std::vector<double> pts = lhs_unit_design(3, 20, 7);
  std::vector<double> linear, bumpy;
  for (std::size_t i = 0; i < 20; ++i) {
    const double* u = pts.data() + 3 * i;
    linear.push_back(1.5 - 2.0 * u[0] + 0.25 * u[1] + 3.0 * u[2]);
    bumpy.push_back(std::sin(6 * u[0]) * std::cos(4 * u[1]) + u[2] * u[2]);
  }
  const CubicRbf lin(pts, 3, linear), bump(pts, 3, bumpy);
  for (std::size_t i = 0; i < 20; ++i) {
    EXPECT_NEAR(bump(pts.data() + 3 * i), bumpy[i], 1e-9);
    EXPECT_NEAR(lin(pts.data() + 3 * i), linear[i], 1e-9);
  }
  // The linear tail carries a linear function whole: the cubic part vanishes off the nodes too.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u01(0, 1);
  for (int k = 0; k < 50; ++k) {
    const double u[3] = {u01(rng), u01(rng), u01(rng)};
    EXPECT_NEAR(lin(u), 1.5 - 2.0 * u[0] + 0.25 * u[1] + 3.0 * u[2], 1e-8);
  }
}

TEST(CubicRbf, RefusesPointsThatCannotCarryTheLinearTail) {
  // Three points on one line of the plane, and a repeated point.
  EXPECT_THROW(CubicRbf({0, 0, 0.5, 0.5, 1, 1}, 2, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(CubicRbf({0, 0, 1, 0, 0, 1, 0, 1}, 2, {1, 2, 3, 4}), std::invalid_argument);
  EXPECT_THROW(CubicRbf({0, 0, 1, 0}, 2, {1, 2}), std::invalid_argument);  // fewer than dim + 1
}

// Branin on [-5, 10] x [0, 15] (Dixon & Szego 1978): three global minima of 0.397887.
double branin(const std::vector<double>& u) {
  const double x = -5 + 15 * u[0], y = 15 * u[1];
  const double b = 5.1 / (4 * M_PI * M_PI), c = 5 / M_PI, t = 1 / (8 * M_PI);
  return std::pow(y - b * x * x + c * x - 6, 2) + 10 * (1 - t) * std::cos(x) + 10;
}

TEST(SurrogateSearch, FindsBraninsGlobalMinimumWithFewEvaluations) {
  FunctionProblem p(2, branin);
  const std::vector<double> design = lhs_unit_design(2, 32, 1);
  std::vector<double> values;
  for (std::size_t i = 0; i < 32; ++i) values.push_back(branin({design[2 * i], design[2 * i + 1]}));
  const double design_best = *std::min_element(values.begin(), values.end());
  detail::SurrogateSearchOptions o;
  std::vector<LocalResult> evaluated;
  const LocalResult best = detail::surrogate_search(p, design, values, o, evaluated);
  // At most two points a round. The search finds a global minimum's basin, not its bottom
  // (the polish of population.cpp does that): within 0.2 % of the function's range over the box
  // (about 300) and 0.05 of the box's side from one of the three minimisers.
  EXPECT_LE(p.evaluations, 2 * o.rounds);
  EXPECT_EQ(evaluated.size(), 32u + static_cast<std::size_t>(p.evaluations));
  EXPECT_LT(best.f, design_best);
  EXPECT_LT(best.f, 0.397887 + 0.6);
  EXPECT_EQ(best.f, branin(best.u));
  double nearest = INFINITY;
  for (const auto& m : {std::array<double, 2>{-M_PI, 12.275}, {M_PI, 2.275}, {9.42478, 2.475}})
    nearest = std::min(nearest, std::hypot(best.u[0] - (m[0] + 5) / 15, best.u[1] - m[1] / 15));
  EXPECT_LT(nearest, 0.05);
}

TEST(SurrogateSearch, ConvergesOnASmoothBowlAndStopsWhenTheSurfaceSettles) {
  const auto bowl = [](const std::vector<double>& u) {
    return 2 + 3 * std::pow(u[0] - 0.3, 2) + std::pow(u[1] - 0.7, 2) + 5 * std::pow(u[2] - 0.55, 2);
  };
  FunctionProblem p(3, bowl);
  const std::vector<double> design = lhs_unit_design(3, 48, 2);
  std::vector<double> values;
  for (std::size_t i = 0; i < 48; ++i)
    values.push_back(bowl({design[3 * i], design[3 * i + 1], design[3 * i + 2]}));
  detail::SurrogateSearchOptions o;
  o.rounds = 200;
  std::vector<LocalResult> evaluated;
  const LocalResult best = detail::surrogate_search(p, design, values, o, evaluated);
  EXPECT_NEAR(best.f, 2.0, 1e-3);
  // It stopped by the settling rule, long before the round limit.
  EXPECT_LT(p.evaluations, 60);
}

TEST(CollisionMemo, GivesTheEnginesResultsAndRunsEachCollisionOnce) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const EngineOptions engine = FitOptions{}.engine;
  std::vector<CollisionCase> cases = {
      {{1.0, -3.0, 2.0}, 0.1}, {{0.5, -2.5, -1.0}, -0.4}, {{1.0, -3.0, 2.0}, 0.3}};
  const std::size_t P = model.parameter_count();
  std::vector<double> params;
  for (int i = 0; i < 3; ++i)
    params.insert(params.end(), model.values().begin(), model.values().end());
  params[2 * P + model.index("mu")] = 0.5;
  detail::DirectSimulator sim(model, shape, engine);
  const auto direct = simulate_batch(model, shape, cases, params, engine);
  CollisionMemo memo(collision_memo_scope(model, shape, engine));
  const auto first = memo.run(sim, cases, params, P);
  const std::uint64_t before = collisions_simulated();
  const auto again = memo.run(sim, cases, params, P);
  EXPECT_EQ(collisions_simulated(), before);  // nothing ran the second time
  EXPECT_EQ(memo.hits(), 3u);
  EXPECT_EQ(memo.stored(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(first[i].vout, direct[i].vout);
    EXPECT_EQ(again[i].vout, direct[i].vout);
    EXPECT_EQ(again[i].max_penetration_m, direct[i].max_penetration_m);
  }
  // Another parameter value is another collision.
  params[model.index("en2")] = 0.3;
  memo.run(sim, cases, params, P);
  EXPECT_EQ(memo.stored(), 4u);
  // The scope tells models, shapes and engine settings apart.
  EngineOptions finer = engine;
  finer.dt_s /= 2;
  EXPECT_NE(collision_memo_scope(model, shape, finer), memo.scope());
  EXPECT_NE(collision_memo_scope(model, Shape::cylinder(), engine), memo.scope());
  finer = engine;
  finer.lanes = 8;
  finer.threads = 1;
  EXPECT_EQ(collision_memo_scope(model, shape, finer), memo.scope());
}

// The first `releases` lab triangles, and fit options that average them over a small rule
// (3 orientations searched, 6 polished) from `starts` starts, without intervals: a quick fit.
ImpactSet first_lab_triangles(std::size_t releases) {
  ImpactSet set = read_impact_set(std::string(RICOCHET_SOURCE_DIR) + "/data/lab/triangles.csv");
  set.impacts.resize(releases);
  return set;
}
FitOptions quick_marginal_fit(int starts) {
  FitOptions o;
  o.alpha.mode = AlphaMode::kMarginal;
  o.alpha.marginal_points = 3;
  o.alpha.polish_points = 6;
  o.intervals = false;
  o.starts = starts;
  return o;
}

// A population fit of orientation-averaged triangles by the response surface: every collision
// on the refined rule, far fewer of them than the multi-start, and a memo shared with another
// fit of the same design gives that fit the same answer with fewer collisions.
TEST(SurrogateSearch, ATriangleFitOnTheSurfaceSharesItsDesignThroughTheMemo) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const ImpactSet set = first_lab_triangles(5);
  FitOptions o = quick_marginal_fit(8);
  const PopulationFit multi = calibrate_population(model, shape, set, o);
  o.alpha.search = OrientationSearch::kSurface;
  o.memo = std::make_shared<CollisionMemo>(collision_memo_scope(model, shape, o.engine));
  const std::uint64_t c0 = collisions_simulated();
  const PopulationFit surface = calibrate_population(model, shape, set, o);
  const std::uint64_t c1 = collisions_simulated();
  const PopulationFit again = calibrate_population(model, shape, set, o);
  const std::uint64_t c2 = collisions_simulated();
  EXPECT_TRUE(std::isfinite(surface.error));
  EXPECT_LT(surface.evaluations, multi.evaluations);
  EXPECT_EQ(again.params, surface.params);
  EXPECT_EQ(again.error, surface.error);
  // The design (49 points x 5 releases x 6 orientations) came from the memo the second time.
  EXPECT_EQ((c1 - c0) - (c2 - c1), 49u * 5u * 6u);
}

// The memo's premise for a search's first points (Problem::eval_starts): BOBYQA's start and its
// 2d first interpolation points follow from the start and the initial step, not from the
// objective. Two objectives with minima far apart, from the same design, must send the same
// points through eval_starts, 2d + 1 per start, beside the design's batch.
class StartRecorder final : public detail::Problem {
 public:
  explicit StartRecorder(std::array<double, 3> centre) : centre_(centre) {}
  std::size_t dim() const override { return 3; }
  double eval(const std::vector<double>& u) override {
    double f = 0;
    for (std::size_t k = 0; k < 3; ++k) f += (u[k] - centre_[k]) * (u[k] - centre_[k]);
    return f;
  }
  std::vector<double> eval_starts(const std::vector<double>& points) override {
    // A search's points come one at a time; the design comes in one batch of several.
    if (points.size() == dim()) starts.push_back(points);
    return eval_many(points);
  }
  std::vector<std::vector<double>> starts;  ///< the searches' points through eval_starts

 private:
  std::array<double, 3> centre_;
};

TEST(MultiStart, ItsStartPointsDoNotDependOnTheObjective) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<double> design(3 * 20);
  for (double& x : design) x = u01(rng);
  StartRecorder a({0.1, 0.2, 0.3}), b({0.9, 0.7, 0.6});
  std::vector<LocalResult> ends;
  std::vector<double> values;
  // One start: the best design point of both objectives must be the same one for the points
  // to be comparable, so the design is one point twice (ties go to the first).
  std::vector<double> one(design.begin(), design.begin() + 3);
  one.insert(one.end(), design.begin(), design.begin() + 3);
  detail::multi_start(a, one, 1, 1e-6, 200, ends, values);
  detail::multi_start(b, one, 1, 1e-6, 200, ends, values);
  ASSERT_EQ(a.starts.size(), 7u);
  EXPECT_EQ(a.starts, b.starts);
  // Many starts: 2d + 1 each.
  StartRecorder c({0.5, 0.5, 0.5});
  detail::multi_start(c, design, 6, 1e-6, 200, ends, values);
  EXPECT_EQ(c.starts.size(), 6u * 7u);
}

// The fold fits of an assessment by the default multi-start share the design and every search's
// first points through the memo: a second fit of a subset of the releases gives the answer it
// gives alone, with fewer collisions.
TEST(MultiStart, AFitThroughTheMemoGivesItsOwnAnswerWithFewerCollisions) {
  const Model model = Model::paper();
  const Shape shape = Shape::triangle();
  const ImpactSet set = first_lab_triangles(6);
  ImpactSet fold = set;
  fold.impacts.erase(fold.impacts.begin() + 2);
  FitOptions o = quick_marginal_fit(6);
  const std::uint64_t c0 = collisions_simulated();
  const PopulationFit alone = calibrate_population(model, shape, fold, o);
  const std::uint64_t c1 = collisions_simulated();
  o.memo = std::make_shared<CollisionMemo>(collision_memo_scope(model, shape, o.engine));
  calibrate_population(model, shape, set, o);
  const std::size_t held = o.memo->stored();
  const std::uint64_t c2 = collisions_simulated();
  const PopulationFit shared = calibrate_population(model, shape, fold, o);
  const std::uint64_t c3 = collisions_simulated();
  EXPECT_EQ(shared.params, alone.params);
  EXPECT_EQ(shared.error, alone.error);
  EXPECT_LT(c3 - c2, c1 - c0);
  // More than the design was shared: 49 points x 5 releases x 3 orientations.
  EXPECT_GT((c1 - c0) - (c3 - c2), 49u * 5u * 3u);
  // Only the design and the searches' first points are kept, not every point of the full fit.
  EXPECT_LT(held, static_cast<std::size_t>(c2 - c1));
}

}  // namespace
}  // namespace ricochet::fit
