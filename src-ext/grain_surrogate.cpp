#include "grain_surrogate.hpp"

#include <cmath>
#include <exception>

#include "common/error.hpp"

namespace ricochet::dem {

double grain_value(const std::string& text, const std::string& file, const std::string& name) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size()) return v;
  } catch (const std::exception&) {
  }
  throw InputError(file, 0, name,
                   "value '" + text + "' is not a number: cannot be a surrogate input");
}

OT::KrigingResult fit_kriging(const OT::Sample& u, const OT::Sample& y, double noise_var,
                              const OT::CovarianceModel* fixed) {
  const std::size_t d = u.getDimension();
  const OT::Basis basis = OT::ConstantBasisFactory(d).build();
  OT::CovarianceModel cov =
      fixed ? *fixed
            : OT::CovarianceModel(OT::MaternModel(OT::Point(d, 0.5), OT::Point(1, 1.0), 2.5));
  OT::KrigingAlgorithm algo(u, y, cov, basis);
  if (noise_var > 0) algo.setNoise(OT::Point(u.getSize(), noise_var));
  if (fixed)
    algo.setOptimizeParameters(false);
  else
    algo.setOptimizationBounds(OT::Interval(OT::Point(d, 0.02), OT::Point(d, 2.0)));
  algo.run();
  return algo.getResult();
}

std::array<double, 2> leave_one_out(const OT::Sample& u, const OT::Sample& y, double noise,
                                    const OT::CovarianceModel& cov, std::vector<double>& loo) {
  const std::size_t n = u.getSize(), d = u.getDimension();
  loo.assign(n, 0.0);
  double press = 0, var = 0, ybar = 0;
  for (std::size_t i = 0; i < n; ++i) ybar += y(i, 0) / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    OT::Sample ui(0, d), yi(0, 1);
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) {
        ui.add(u[j]);
        yi.add(y[j]);
      }
    loo[i] = fit_kriging(ui, yi, noise, &cov).getMetaModel()(u[i])[0];
    press += std::pow(y(i, 0) - loo[i], 2);
    var += std::pow(y(i, 0) - ybar, 2);
  }
  return {var > 0 ? 1.0 - press / var : NAN, std::sqrt(press / static_cast<double>(n))};
}

}  // namespace ricochet::dem
