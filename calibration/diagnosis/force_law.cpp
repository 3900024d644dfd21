// The force-residual discovery: the term library and its sparse selection (force_law.hpp).
#include "diagnosis/force_law.hpp"

#include <fmt/format.h>

#include <cmath>

#include "common/error.hpp"

namespace ricochet::diagnosis {

namespace {

constexpr const char* kWhere = "<force residuals>";

double sgn(double x) {
  return x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0;
}

}  // namespace

std::string_view component_name(ForceComponent c) {
  switch (c) {
    case ForceComponent::kNormal:
      return "normal";
    case ForceComponent::kTangential:
      return "tangential";
    case ForceComponent::kMoment:
      return "moment";
  }
  return "?";
}

const std::vector<ForceTerm>& force_terms() {
  using C = ForceComponent;
  static const std::vector<ForceTerm> terms = {
      {"spring", C::kNormal, "c h", "N/m", "linear spring (Katsuragi-Durian k z)",
       [](const ContactSample& s) { return s.h_m; }},
      {"hertz", C::kNormal, "c h^1.5", "N/m^1.5", "Hertz contact",
       [](const ContactSample& s) { return std::pow(s.h_m, 1.5); }},
      {"quadratic_depth", C::kNormal, "c h^2", "N/m^2", "",
       [](const ContactSample& s) { return s.h_m * s.h_m; }},
      {"inertial_drag", C::kNormal, "-c v_n|v_n|", "kg/m",
       "Poncelet / Katsuragi-Durian inertial drag (c = m/d1)",
       [](const ContactSample& s) { return -s.vn_mps * std::abs(s.vn_mps); }},
      {"viscous", C::kNormal, "-c v_n", "N s/m", "viscous damping",
       [](const ContactSample& s) { return -s.vn_mps; }},
      {"depth_drag", C::kNormal, "-c h v_n|v_n|", "kg/m^2", "",
       [](const ContactSample& s) { return -s.h_m * s.vn_mps * std::abs(s.vn_mps); }},
      // One branch term, not one per branch: h on loading plus h on unloading is h itself,
      // and a library with both and the spring would be singular.
      {"branch_spring", C::kNormal, "c h sign(-v_n)", "N/m",
       "hysteresis: stiffer loading than unloading (Walton & Braun 1986)",
       [](const ContactSample& s) { return s.loading ? s.h_m : -s.h_m; }},
      {"ploughing", C::kTangential, "-c sign(v_x) h^2", "N/m^2",
       "Rankine passive earth pressure (c = K_p gamma L / 2)",
       [](const ContactSample& s) { return -sgn(s.vx_mps) * s.h_m * s.h_m; }},
      {"depth_friction_force", C::kTangential, "-c sign(v_t) h", "N/m", "",
       [](const ContactSample& s) { return -sgn(s.vt_mps) * s.h_m; }},
      {"tangential_viscous", C::kTangential, "-c v_t", "N s/m", "viscous damping",
       [](const ContactSample& s) { return -s.vt_mps; }},
      {"tangential_drag", C::kTangential, "-c v_t|v_t|", "kg/m", "inertial drag",
       [](const ContactSample& s) { return -s.vt_mps * std::abs(s.vt_mps); }},
      {"depth_rolling", C::kMoment, "-c sign(omega) h", "N", "",
       [](const ContactSample& s) { return -sgn(s.omega_radps) * s.h_m; }},
      {"rolling_viscous", C::kMoment, "-c omega", "N m s/rad", "viscous rolling damping",
       [](const ContactSample& s) { return -s.omega_radps; }},
  };
  return terms;
}

std::vector<const ForceTerm*> force_terms(ForceComponent c) {
  std::vector<const ForceTerm*> out;
  for (const ForceTerm& t : force_terms())
    if (t.component == c) out.push_back(&t);
  return out;
}

std::vector<ComponentLaw> discover_force_law(const std::vector<ReleaseResidual>& releases,
                                             const stats::SparseOptions& options) {
  for (std::size_t r = 0; r < releases.size(); ++r) {
    const ReleaseResidual& rel = releases[r];
    if (rel.residual.size() != rel.samples.size())
      throw InputError(kWhere, 0, "residual",
                       fmt::format("release {}: {} residuals for {} samples", r,
                                   rel.residual.size(), rel.samples.size()));
    for (std::size_t i = 0; i < rel.samples.size(); ++i) {
      const ContactSample& s = rel.samples[i];
      if (!std::isfinite(s.h_m) || !std::isfinite(s.vn_mps) || !std::isfinite(s.vt_mps) ||
          !std::isfinite(s.vx_mps) || !std::isfinite(s.omega_radps))
        throw InputError(kWhere, 0, "samples",
                         fmt::format("release {}, sample {}: a state is not finite", r, i));
    }
  }
  std::vector<ComponentLaw> laws;
  for (std::size_t c = 0; c < kForceComponents; ++c) {
    const auto comp = static_cast<ForceComponent>(c);
    const std::vector<const ForceTerm*> terms = force_terms(comp);
    std::vector<double> x, y;
    std::vector<std::size_t> group;
    std::size_t used_releases = 0;
    for (std::size_t r = 0; r < releases.size(); ++r) {
      bool any = false;
      for (std::size_t i = 0; i < releases[r].samples.size(); ++i) {
        const double res = releases[r].residual[i][c];
        if (!std::isfinite(res)) continue;  // this component not measured here
        for (const ForceTerm* t : terms) x.push_back(t->value(releases[r].samples[i]));
        y.push_back(res);
        group.push_back(r);
        any = true;
      }
      used_releases += any;
    }
    if (y.empty()) continue;
    if (used_releases < 2)
      throw InputError(kWhere, 0, "releases",
                       fmt::format("the {} residual has samples in {} release(s); the "
                                   "cross-validation over releases needs two at least",
                                   component_name(comp), used_releases));
    ComponentLaw law;
    law.component = comp;
    law.releases = used_releases;
    law.samples = y.size();
    const stats::SparseDesign design{x, terms.size(), y, group};
    law.fit = stats::sparse_regression(design, options);
    double ss = 0, sh = 0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      ss += y[i] * y[i];
      sh += (y[i] - law.fit.heldout[i]) * (y[i] - law.fit.heldout[i]);
    }
    law.rms_residual = std::sqrt(ss / static_cast<double>(y.size()));
    law.heldout_rms = std::sqrt(sh / static_cast<double>(y.size()));
    const char* symbol = comp == ForceComponent::kMoment ? "M" : c == 0 ? "F_n" : "F_t";
    for (std::size_t j = 0; j < terms.size(); ++j) {
      DiscoveredTerm d;
      d.term = terms[j];
      d.coefficient = law.fit.coef[j];
      d.lo = law.fit.lo[j];
      d.hi = law.fit.hi[j];
      d.inclusion = law.fit.inclusion[j];
      d.selected = law.fit.active[j];
      if (d.selected)
        law.text += fmt::format(
            "{}{} += {}, c = {:.4g} {} [{:.4g}, {:.4g}]{}", law.text.empty() ? "" : "; ", symbol,
            d.term->expression, d.coefficient, d.term->unit, d.lo, d.hi,
            d.term->literature.empty() ? std::string() : fmt::format(" ({})", d.term->literature));
      law.terms.push_back(d);
    }
    if (law.text.empty()) law.text = "nothing found";
    laws.push_back(std::move(law));
  }
  return laws;
}

}  // namespace ricochet::diagnosis
