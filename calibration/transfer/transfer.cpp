// Stochastic transfer-matrix model (paper section 3, Eq. 2). See transfer.hpp.
#include "transfer/transfer.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>

#include "common/error.hpp"
#include "common/h5.hpp"

namespace ricochet::transfer {
namespace {

Eigen::MatrixXd as_matrix(const std::vector<Vel3>& v) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t r = 0; r < v.size(); ++r)
    for (int c = 0; c < 3; ++c) m(static_cast<Eigen::Index>(r), c) = v[r][c];
  return m;
}

/// Least squares X B = Y (B = M^T) with standard errors; X is n x 3.
FullFit full_lsq(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  FullFit f;
  f.n = static_cast<std::size_t>(X.rows());
  if (X.rows() < 4)
    throw std::invalid_argument("transfer: the full 3x3 matrix needs at least 4 releases, got " +
                                std::to_string(X.rows()));
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < 3)
    throw std::invalid_argument(
        "transfer: the incident velocities are linearly dependent: the full matrix is not "
        "identifiable");
  const Eigen::MatrixXd B = qr.solve(Y);  // 3 x 3, column i = row i of M
  const Eigen::Matrix3d xtx_inv = (X.transpose() * X).inverse();
  const double dof = static_cast<double>(X.rows() - 3);
  for (int i = 0; i < 3; ++i) {
    const double rss = (Y.col(i) - X * B.col(i)).squaredNorm();
    f.residual_std[i] = std::sqrt(rss / dof);
    for (int j = 0; j < 3; ++j) {
      f.m[i][j] = B(j, i);
      f.se[i][j] = f.residual_std[i] * std::sqrt(xtx_inv(j, j));
    }
  }
  // Condition number of the column-equilibrated design: scale-free measure of collinearity.
  Eigen::MatrixXd Xs = X;
  for (int j = 0; j < 3; ++j) Xs.col(j) /= X.col(j).norm();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Xs);
  const auto& s = svd.singularValues();
  f.condition_number = s(0) / s(s.size() - 1);
  return f;
}

DiagonalFit diagonal_from(const std::vector<Vel3>& in, const std::vector<Vel3>& out) {
  if (in.empty()) throw std::invalid_argument("transfer: Eq. 2 needs at least one release");
  DiagonalFit f;
  f.n = in.size();
  for (int c = 0; c < 3; ++c) {
    double sum_in = 0, sum_out = 0;
    double lo_in = in[0][c], hi_in = in[0][c], lo_out = out[0][c], hi_out = out[0][c];
    for (std::size_t r = 0; r < in.size(); ++r) {
      sum_in += in[r][c];
      sum_out += out[r][c];
      lo_in = std::min(lo_in, in[r][c]);
      hi_in = std::max(hi_in, in[r][c]);
      lo_out = std::min(lo_out, out[r][c]);
      hi_out = std::max(hi_out, out[r][c]);
    }
    const double n = static_cast<double>(in.size());
    f.mean_in[c] = sum_in / n;
    f.mean_out[c] = sum_out / n;
    f.min_in[c] = lo_in;
    f.max_in[c] = hi_in;
    f.min_out[c] = lo_out;
    f.max_out[c] = hi_out;
    if (f.mean_in[c] == 0 || lo_in == 0 || hi_in == 0)
      throw std::invalid_argument(std::string("transfer: Eq. 2 divides by the mean, minimum and "
                                              "maximum of the incident ") +
                                  kComponentNames[static_cast<std::size_t>(c)] +
                                  ", and one of them is zero");
    // Paper Eq. 2: ratio of means, and a quarter of the spread between the ratio of maxima and
    // the ratio of minima (signed extrema, as the printed Table 3 values require).
    f.model.a[c] = f.mean_out[c] / f.mean_in[c];
    f.model.delta_a[c] = 0.25 * std::abs(hi_out / hi_in - lo_out / lo_in);
  }
  return f;
}

Vel3 diagonal_lsq_from(const std::vector<Vel3>& in, const std::vector<Vel3>& out) {
  Vel3 a{};
  for (int c = 0; c < 3; ++c) {
    double sxy = 0, sxx = 0;
    for (std::size_t r = 0; r < in.size(); ++r) {
      sxy += in[r][c] * out[r][c];
      sxx += in[r][c] * in[r][c];
    }
    if (sxx == 0) throw std::invalid_argument("transfer: an incident component is zero everywhere");
    a[c] = sxy / sxx;
  }
  return a;
}

/// Uniform on [0, 1) from the 53 high bits: unlike std::uniform_real_distribution, the mapping is
/// fixed, so samples are identical across standard libraries.
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace

std::vector<Vel3> incident(const ImpactSet& set) {
  std::vector<Vel3> v;
  v.reserve(set.size());
  for (const Impact& i : set.impacts) v.push_back(i.vin);
  return v;
}

std::vector<Vel3> reflected(const ImpactSet& set) {
  std::vector<Vel3> v;
  v.reserve(set.size());
  for (const Impact& i : set.impacts) v.push_back(i.vout);
  return v;
}

std::vector<double> component(std::span<const Vel3> v, int c) {
  std::vector<double> out;
  out.reserve(v.size());
  for (const Vel3& e : v) out.push_back(e[static_cast<std::size_t>(c)]);
  return out;
}

DiagonalFit fit_diagonal(const ImpactSet& set) {
  return diagonal_from(incident(set), reflected(set));
}

Vel3 fit_diagonal_lsq(const ImpactSet& set) {
  return diagonal_lsq_from(incident(set), reflected(set));
}

FullFit fit_full(const ImpactSet& set) {
  return full_lsq(as_matrix(incident(set)), as_matrix(reflected(set)));
}

LooComparison leave_one_out(const ImpactSet& set) {
  const std::vector<Vel3> in = incident(set), out = reflected(set);
  const std::size_t n = in.size();
  if (n < 5)
    throw std::invalid_argument("transfer: leave-one-out needs at least 5 releases, got " +
                                std::to_string(n));
  LooComparison loo;
  loo.n = n;
  Vel3 sse_const{}, sse_diag{}, sse_dlsq{}, sse_full{};
  for (std::size_t k = 0; k < n; ++k) {
    std::vector<Vel3> tin, tout;
    for (std::size_t r = 0; r < n; ++r)
      if (r != k) {
        tin.push_back(in[r]);
        tout.push_back(out[r]);
      }
    const DiagonalFit d = diagonal_from(tin, tout);
    const Vel3 dl = diagonal_lsq_from(tin, tout);
    const FullFit f = full_lsq(as_matrix(tin), as_matrix(tout));
    Vel3 pd{}, pf{};
    for (int i = 0; i < 3; ++i) {
      pd[i] = d.model.a[i] * in[k][i];
      pf[i] = 0;
      for (int j = 0; j < 3; ++j) pf[i] += f.m[i][j] * in[k][j];
      const double e_const = out[k][i] - d.mean_out[i];
      const double e_dlsq = out[k][i] - dl[i] * in[k][i];
      sse_const[i] += e_const * e_const;
      sse_diag[i] += (out[k][i] - pd[i]) * (out[k][i] - pd[i]);
      sse_dlsq[i] += e_dlsq * e_dlsq;
      sse_full[i] += (out[k][i] - pf[i]) * (out[k][i] - pf[i]);
    }
    loo.predicted_diagonal.push_back(pd);
    loo.predicted_full.push_back(pf);
  }
  for (int i = 0; i < 3; ++i) {
    const double dn = static_cast<double>(n);
    loo.rmse_constant[i] = std::sqrt(sse_const[i] / dn);
    loo.rmse_diagonal[i] = std::sqrt(sse_diag[i] / dn);
    loo.rmse_diagonal_lsq[i] = std::sqrt(sse_dlsq[i] / dn);
    loo.rmse_full[i] = std::sqrt(sse_full[i] / dn);
    loo.full_improves[static_cast<std::size_t>(i)] = loo.rmse_full[i] < loo.rmse_diagonal[i];
  }
  return loo;
}

std::vector<Vel3> sample_reflected(const DiagonalModel& model, std::span<const Vel3> vin,
                                   std::size_t replicates, std::uint64_t seed) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(model.a[c]) || !std::isfinite(model.delta_a[c]) || model.delta_a[c] < 0)
      throw std::invalid_argument("transfer: model coefficients must be finite with dA >= 0");
  std::mt19937_64 rng(seed);
  std::vector<Vel3> out;
  out.reserve(vin.size() * replicates);
  for (const Vel3& v : vin)
    for (std::size_t r = 0; r < replicates; ++r) {
      Vel3 o{};
      for (int c = 0; c < 3; ++c) {
        // Table 3 note: a new A_ii from U[A - dA, A + dA] for each single rebound.
        const double a = model.a[c] - model.delta_a[c] + 2 * model.delta_a[c] * uniform01(rng);
        o[c] = a * v[c];
      }
      out.push_back(o);
    }
  return out;
}

DistributionComparison compare_distributions(std::span<const Vel3> measured,
                                             std::span<const Vel3> predicted) {
  DistributionComparison d;
  d.n_measured = measured.size();
  d.n_predicted = predicted.size();
  for (int c = 0; c < 3; ++c)
    d.ks[static_cast<std::size_t>(c)] =
        stats::ks_two_sample(component(measured, c), component(predicted, c));
  return d;
}

void write_model_h5(const StoredModel& model, const std::string& path) {
  h5::File f(path, h5::File::Mode::kReadWrite);
  f.remove("/transfer");
  f.create_group("/transfer");
  f.set_attr("/transfer", "schema", std::string("ricochet-transfer-1"));
  f.set_attr("/transfer", "source", model.source);
  f.set_attr("/transfer", "where", model.where);
  f.set_attr("/transfer", "n", static_cast<double>(model.n));
  f.set_attr("/transfer", "equation", std::string("Garcia et al. (2020) Eq. 2"));
  f.write("/transfer/A", std::span<const double>(model.diagonal.a));
  f.write("/transfer/dA", std::span<const double>(model.diagonal.delta_a));
  if (model.has_full) {
    std::vector<double> m, se;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m.push_back(model.full[i][j]);
        se.push_back(model.full_se[i][j]);
      }
    f.write("/transfer/M", m, {3, 3});
    f.write("/transfer/M_se", se, {3, 3});
  }
  f.flush();
}

StoredModel read_model_h5(const std::string& path) {
  std::optional<h5::File> opened;
  try {
    opened.emplace(path, h5::File::Mode::kRead);
  } catch (const std::runtime_error& e) {
    throw InputError(path, 0, "", std::string("cannot read the model file: ") + e.what());
  }
  h5::File& f = *opened;
  if (!f.exists("/transfer") || !f.has_attr("/transfer", "schema") ||
      f.attr_string("/transfer", "schema") != "ricochet-transfer-1")
    throw InputError(path, 0, "/transfer",
                     "not a transfer model (write one with `ricochet transfer fit DATA --out "
                     "FIT.h5`)");
  StoredModel m;
  for (const char* name : {"A", "dA"}) {
    const std::string p = std::string("/transfer/") + name;
    if (!f.exists(p)) throw InputError(path, 0, p, "missing dataset");
    const std::vector<double> v = f.read_doubles(p);
    if (v.size() != 3) throw InputError(path, 0, p, "expected 3 values");
    for (double e : v)
      if (!std::isfinite(e)) throw InputError(path, 0, p, "values must be finite");
    Vel3& dst = std::string(name) == "A" ? m.diagonal.a : m.diagonal.delta_a;
    std::copy(v.begin(), v.end(), dst.begin());
  }
  for (double e : m.diagonal.delta_a)
    if (e < 0) throw InputError(path, 0, "/transfer/dA", "half-widths must be >= 0");
  if (f.exists("/transfer/M")) {
    const std::vector<double> v = f.read_doubles("/transfer/M");
    const std::vector<double> se =
        f.exists("/transfer/M_se") ? f.read_doubles("/transfer/M_se") : std::vector<double>(9, 0.0);
    if (v.size() != 9 || se.size() != 9)
      throw InputError(path, 0, "/transfer/M", "expected a 3x3 matrix");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m.full[i][j] = v[static_cast<std::size_t>(3 * i + j)];
        m.full_se[i][j] = se[static_cast<std::size_t>(3 * i + j)];
      }
    m.has_full = true;
  }
  m.source = f.has_attr("/transfer", "source") ? f.attr_string("/transfer", "source") : "";
  m.where = f.has_attr("/transfer", "where") ? f.attr_string("/transfer", "where") : "";
  m.n =
      f.has_attr("/transfer", "n") ? static_cast<std::size_t>(f.attr_double("/transfer", "n")) : 0;
  return m;
}

}  // namespace ricochet::transfer
