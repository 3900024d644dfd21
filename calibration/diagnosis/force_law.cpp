// The force-residual discovery: the term library and its sparse selection (force_law.hpp).
#include "diagnosis/force_law.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/error.hpp"

namespace ricochet::diagnosis {

namespace {

constexpr const char* kWhere = "<force residuals>";

}  // namespace

std::vector<const ForceTerm*> named_force_terms(const std::vector<std::string>& names,
                                                const std::string& where,
                                                const std::string& field) {
  std::vector<const ForceTerm*> out;
  for (const std::string& name : names) {
    // The term's own name or its effect's (force_term_effect_name: "term_<name>").
    const ForceTerm* t = effects::find_force_term(name);
    for (const ForceTerm& term : force_terms())
      if (!t && effects::force_term_effect_name(term) == name) t = &term;
    if (!t)
      throw InputError(where, 0, field,
                       fmt::format("unknown force term '{}'; known: the {}", name,
                                   effects::force_term_family_text()));
    if (std::find(out.begin(), out.end(), t) != out.end())
      throw InputError(where, 0, field, fmt::format("the term '{}' is named twice", t->name));
    out.push_back(t);
  }
  return out;
}

std::vector<ComponentLaw> discover_force_law(const std::vector<ReleaseResidual>& releases,
                                             const stats::SparseOptions& options,
                                             std::span<const ForceTerm* const> named) {
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
    stats::SparseOptions o = options;
    if (!named.empty()) {
      std::uint32_t support = 0;
      for (std::size_t j = 0; j < terms.size(); ++j)
        if (std::find(named.begin(), named.end(), terms[j]) != named.end()) support |= 1u << j;
      o.support = support;
    }
    law.fit = stats::sparse_regression(design, o);
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
            "{}{} += {}, c = {:.4g} {} [{:.4g}, {:.4g}]{}{}", law.text.empty() ? "" : "; ", symbol,
            d.term->expression, d.coefficient, d.term->unit, d.lo, d.hi,
            // A named law is not selected, so only a discovered term has a frequency to show.
            named.empty() && o.bootstrap > 0
                ? fmt::format(", in {:.0f} % of resamples", 100 * d.inclusion)
                : std::string(),
            d.term->literature.empty() ? std::string() : fmt::format(" ({})", d.term->literature));
      law.terms.push_back(d);
    }
    if (law.text.empty()) law.text = named.empty() ? "nothing found" : "no term named";
    laws.push_back(std::move(law));
  }
  return laws;
}

}  // namespace ricochet::diagnosis
