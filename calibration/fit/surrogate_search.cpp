#include "fit/surrogate_search.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace ricochet::fit::detail {

CubicRbf::CubicRbf(const std::vector<double>& points, std::size_t dim,
                   const std::vector<double>& values)
    : dim_(dim), points_(points) {
  const std::size_t n = values.size(), m = dim + 1;
  if (dim == 0 || points.size() != n * dim || n < m)
    throw std::invalid_argument("CubicRbf: at least dim + 1 points of dim coordinates are needed");
  // The saddle-point system [Phi P; P^T 0] [lambda; c] = [f; 0] (Powell 1992, section 5): the
  // cubic is conditionally positive definite of order 2, so it is nonsingular whenever the
  // points determine a linear function.
  Eigen::MatrixXd a =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n + m), static_cast<Eigen::Index>(n + m));
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n + m));
  for (std::size_t i = 0; i < n; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    for (std::size_t j = 0; j < i; ++j) {
      double r2 = 0;
      for (std::size_t k = 0; k < dim; ++k) {
        const double dx = points[i * dim + k] - points[j * dim + k];
        r2 += dx * dx;
      }
      const double phi = r2 * std::sqrt(r2);
      a(ii, static_cast<Eigen::Index>(j)) = a(static_cast<Eigen::Index>(j), ii) = phi;
    }
    const auto tail = static_cast<Eigen::Index>(n);
    a(ii, tail) = a(tail, ii) = 1.0;
    for (std::size_t k = 0; k < dim; ++k) {
      const auto col = static_cast<Eigen::Index>(n + 1 + k);
      a(ii, col) = a(col, ii) = points[i * dim + k];
    }
    b(ii) = values[i];
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (lu.rank() < a.rows())
    throw std::invalid_argument("CubicRbf: the points lie on a hyperplane (or repeat)");
  const Eigen::VectorXd x = lu.solve(b);
  lambda_.assign(x.data(), x.data() + n);
  tail_.assign(x.data() + n, x.data() + n + m);
}

double CubicRbf::operator()(const double* u) const {
  double s = tail_[0];
  for (std::size_t k = 0; k < dim_; ++k) s += tail_[k + 1] * u[k];
  for (std::size_t i = 0; i < lambda_.size(); ++i) {
    double r2 = 0;
    for (std::size_t k = 0; k < dim_; ++k) {
      const double dx = u[k] - points_[i * dim_ + k];
      r2 += dx * dx;
    }
    s += lambda_[i] * r2 * std::sqrt(r2);
  }
  return s;
}

namespace {

// The surface as a problem for minimize_local, with the CORS distance constraint as a
// quadratic penalty (zero outside the excluded balls, so the constrained minimum is the
// surface's own value there).
class SurfaceProblem final : public Problem {
 public:
  SurfaceProblem(const CubicRbf& s, const std::vector<double>& points, std::size_t dim,
                 double min_distance, double penalty)
      : s_(s), points_(points), dim_(dim), min_distance_(min_distance), penalty_(penalty) {}
  std::size_t dim() const override { return dim_; }
  double eval(const std::vector<double>& u) override {
    double f = s_(u.data());
    if (min_distance_ > 0) {
      const double d = distance_to_points(u);
      if (d < min_distance_) {
        const double short_by = (min_distance_ - d) / min_distance_;
        f += penalty_ * short_by * short_by;
      }
    }
    return f;
  }
  double distance_to_points(const std::vector<double>& u) const {
    double best = INFINITY;
    for (std::size_t i = 0; (i + 1) * dim_ <= points_.size(); ++i) {
      double r2 = 0;
      for (std::size_t k = 0; k < dim_; ++k) {
        const double dx = u[k] - points_[i * dim_ + k];
        r2 += dx * dx;
      }
      best = std::min(best, r2);
    }
    return std::sqrt(best);
  }

 private:
  const CubicRbf& s_;
  const std::vector<double>& points_;
  std::size_t dim_;
  double min_distance_, penalty_;
};

double chebyshev_to_points(const std::vector<double>& u, const std::vector<double>& points,
                           std::size_t dim) {
  double best = INFINITY;
  for (std::size_t i = 0; (i + 1) * dim <= points.size(); ++i) {
    double m = 0;
    for (std::size_t k = 0; k < dim; ++k) m = std::max(m, std::fabs(u[k] - points[i * dim + k]));
    best = std::min(best, m);
  }
  return best;
}

// Values above the median replaced by it (file comment); non-finite values count as large.
std::vector<double> clipped(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  if (finite.empty()) return std::vector<double>(values.size(), 0.0);
  std::vector<double> sorted = finite;
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  const double median = *mid;
  std::vector<double> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    out[i] = std::isfinite(values[i]) ? std::min(values[i], median) : median;
  return out;
}

// The surface's minimum (with the distance penalty when min_distance > 0) from the `starts`
// best evaluated points.
LocalResult surface_minimum(const CubicRbf& s, const std::vector<double>& points,
                            const std::vector<double>& values, std::size_t dim, int starts,
                            double min_distance, double penalty) {
  SurfaceProblem sp(s, points, dim, min_distance, penalty);
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  const std::vector<char> all(dim, 1);
  LocalResult best;
  const std::size_t runs = std::min<std::size_t>(order.size(), static_cast<std::size_t>(starts));
  for (std::size_t r = 0; r < runs; ++r) {
    const std::size_t i = order[r];
    const std::vector<double> u0(points.begin() + i * dim, points.begin() + (i + 1) * dim);
    // A start is an evaluated point, inside the excluded ball when exploring: a first step of
    // the ball's size lets BOBYQA's first model reach out of it.
    const LocalResult e = minimize_local(sp, u0, all, std::max(0.05, min_distance), 1e-4,
                                         200 * static_cast<int>(dim));
    if (e.f < best.f) best = e;
  }
  return best;
}

}  // namespace

LocalResult surrogate_search(Problem& problem, const std::vector<double>& points_in,
                             const std::vector<double>& values_in, const SurrogateSearchOptions& o,
                             std::vector<LocalResult>& evaluated) {
  const std::size_t d = problem.dim();
  std::vector<double> points = points_in;
  std::vector<double> values = values_in;
  if (d == 0 || points.size() != values.size() * d)
    throw std::invalid_argument("surrogate_search: one value per point of problem.dim()");
  int settled = 0;  // consecutive rounds whose surface minimum was already evaluated
  for (int round = 0; round < o.rounds && settled < 2; ++round) {
    const std::vector<double> f = clipped(values);
    const CubicRbf s(points, d, f);
    const auto [lo, hi] = std::minmax_element(f.begin(), f.end());
    const double penalty = 100.0 * std::max(*hi - *lo, 1e-12);
    std::vector<double> next;
    const LocalResult exploit = surface_minimum(s, points, f, d, o.starts, 0.0, 0.0);
    if (chebyshev_to_points(exploit.u, points, d) > o.xtol) {
      next = exploit.u;
      settled = 0;
    } else {
      ++settled;
    }
    const double beta = o.explore.empty() ? 0.0 : o.explore[round % o.explore.size()];
    if (beta > 0) {
      const LocalResult explore = surface_minimum(s, points, f, d, o.starts, beta, penalty);
      std::vector<double> all = points;
      all.insert(all.end(), next.begin(), next.end());
      if (chebyshev_to_points(explore.u, all, d) > o.xtol)
        next.insert(next.end(), explore.u.begin(), explore.u.end());
    }
    if (next.empty()) continue;
    const std::vector<double> v = problem.eval_many(next);
    points.insert(points.end(), next.begin(), next.end());
    values.insert(values.end(), v.begin(), v.end());
  }
  evaluated.clear();
  LocalResult best;
  for (std::size_t i = 0; i < values.size(); ++i) {
    LocalResult r{std::vector<double>(points.begin() + i * d, points.begin() + (i + 1) * d),
                  values[i]};
    if (std::isfinite(r.f) && r.f < best.f) best = r;
    evaluated.push_back(std::move(r));
  }
  return best;
}

}  // namespace ricochet::fit::detail
