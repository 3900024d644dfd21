#include "effects/catalog.hpp"

#include <cstdio>
#include <initializer_list>
#include <string_view>
#include <vector>

#include "effects/coefficient_law.hpp"
#include "effects/force_term.hpp"

namespace ricochet::effects {
namespace {

// Appends the parts to `out` (appending, rather than chains of operator+, keeps GCC 12's
// -Wrestrict false positive on `"literal" + std::string` away).
void put(std::string& out, std::initializer_list<std::string_view> parts) {
  for (std::string_view p : parts) out.append(p);
}

// A number as `ricochet effects` prints bounds: shortest of %g.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// "`kn` [N/m] 100000 to 1e+09, normal_stiffness, fixed (identified by contact_features)".
std::string parameter_cell(const Effect& e) {
  std::string s;
  for (const ParameterSpec& p : e.parameters()) {
    put(s, {s.empty() ? "" : "; ", "`", p.name, "` [", p.unit, "] ", num(p.lower), " to ",
            num(p.upper)});
    if (p.role != ParameterRole::kOther) put(s, {", ", role_name(p.role)});
    put(s, {p.calibrated ? ", calibrated" : ", fixed"});
    if (p.identified_by != IdentifiedBy::kRebound)
      put(s, {" (identified by ", identified_by_name(p.identified_by), ")"});
  }
  return s.empty() ? "none" : s;
}

// "residual vy ~ abs_vin_y; param restitution ~ speed_in; contact features biased".
std::string signature_cell(const Effect& e) {
  const Signature sig = e.signature();
  std::string s;
  for (const SignatureTrend& t : sig.trends)
    put(s, {s.empty() ? "" : "; ", t.quantity, " ~ ", t.feature});
  if (sig.contact_bias) put(s, {s.empty() ? "" : "; ", "contact features biased"});
  return s.empty() ? "none (the paper's law)" : s;
}

// "`a`, `b`, `c`" (or "{a, b, c}" when `set`).
template <class Words>
std::string list(const Words& words, bool set = false) {
  std::string s;
  for (std::string_view w : words)
    put(s, {s.empty() ? "" : ", ", set ? "" : "`", w, set ? "" : "`"});
  return set ? "{" + s + "}" : s;
}

template <class Enum>
std::vector<std::string_view> words(std::size_t count, std::string_view (*name)(Enum)) {
  std::vector<std::string_view> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(name(static_cast<Enum>(i)));
  return out;
}

std::string force_term_paragraph() {
  std::string out;
  put(out, {"## Force terms\n\n`term_<name>` (", std::to_string(force_terms().size()),
            " effects, page [force_term.md](force_term.md)): the force-residual discovery's "
            "library as effects, so that a discovered law goes into a model file. One parameter "
            "`c_<name>` each, neutral at 0, c > 0 resists the motion; not tried by `diagnose` "
            "unless named.\n\n| term | adds to | expression | unit of c | bound of abs(c) | law |\n"
            "|---|---|---|---|---|---|\n"});
  for (const ForceTerm& t : force_terms()) {
    char bound[32];
    std::snprintf(bound, sizeof bound, "%.3g", force_term_bound(t));
    std::string expression;  // a | would end the table cell, even in a code span (GFM)
    for (char ch : t.expression) expression += ch == '|' ? std::string("\\|") : std::string(1, ch);
    put(out, {"| `term_", t.name, "` | ", component_name(t.component),
              t.at_centre ? " (at the centre)" : "", " | `", expression, "` | ", t.unit, " | ",
              bound, " | ", t.literature, " |\n"});
  }
  return out;
}

std::string generated_paragraph(std::size_t count) {
  std::string tags, out;
  for (const LawVariable& v : law_variable_info())
    put(tags, {tags.empty() ? "" : ", ", v.name, " `", v.tag, "`"});
  put(out, {"## Generated coefficient laws\n\n`<coefficient>_<variable>_<form>` (",
            std::to_string(count),
            " effects, stage coefficient, page [coefficient_law.md](coefficient_law.md)): any "
            "coefficient in ",
            list(law_coefficients(), true), " as a linear or power function of a variable in ",
            list(law_variables(), true), ", form in ", list(law_forms(), true),
            ". One parameter each, neutral at 0: `c_<coefficient>_<tag>` (linear) or "
            "`p_<coefficient>_<tag>` (power), with the variable's tag: ",
            tags, ".\n"});
  return out;
}

std::string vocabulary_section() {
  std::vector<std::string_view> residuals =
      words<TrendQuantity>(kResidualQuantityCount, quantity_name);
  std::string out;
  put(out, {"## The words of a declaration\n\n"
            "What an effect declares, in these words only: the registry refuses any other "
            "(calibration/effects/effect.hpp).\n\n"
            "- Parameter roles (`ParameterRole`): ",
            list(words<ParameterRole>(kParameterRoleCount, role_name)),
            ". The stable time step, the fused kernel, the identifiability statements, the "
            "diagnosis and the Monte Carlo's ranges read parameters by role, never by name.\n"
            "- What identifies a parameter (`IdentifiedBy`): ",
            list(words<IdentifiedBy>(kIdentifiedByCount, identified_by_name)),
            ". A parameter identified by the contact features is calibrated when the error "
            "compares them and is a nuisance direction of the score test on velocities only.\n"
            "- Signature quantities: ",
            list(residuals),
            ", `param <role>` (a calibrated parameter of the base model, by its role).\n"
            "- Signature features: ",
            list(words<ImpactFeature>(kImpactFeatureCount, feature_name)), ".\n"});
  return out;
}

}  // namespace

std::string catalog_markdown(const EffectRegistry& registry) {
  std::string out =
      "<!-- Generated by `ricochet effects --markdown` from the effects' declarations: do not "
      "edit.\n     Regenerate: build/cli/ricochet effects --markdown > docs/effects/README.md "
      "-->\n"
      "# The effect catalog\n\n"
      "A contact model is a composition of effects (docs/architecture.md). The paper's law is "
      "three effects (normal, tangential, rolling); the others are candidate missing physics. "
      "Each row is what the effect declares about itself (calibration/effects/<name>.cpp); its "
      "page gives the equation, the parameters, the signature in residuals and the "
      "reference.\n\n"
      "| effect | stage | changes | depends on | parameters | signature (quantity ~ feature) | "
      "page |\n"
      "|---|---|---|---|---|---|---|\n";
  std::size_t generated = 0, terms = 0;
  for (const Effect* e : registry.all()) {
    if (e->generated()) {
      ++(e->default_candidate() ? generated : terms);
      continue;
    }
    const LawKind kind = e->kind();
    put(out, {"| ", e->name(), " | ", stage_name(e->stage()), " | ", family_name(kind.family),
              " | ", variable_name(kind.variable), " | ", parameter_cell(*e), " | ",
              signature_cell(*e), " | [", e->name(), ".md](", e->name(), ".md) |\n"});
  }
  if (generated > 0) put(out, {"\n", generated_paragraph(generated)});
  if (terms > 0) put(out, {"\n", force_term_paragraph()});
  put(out, {"\n", vocabulary_section(),
            "\n## Write your own\n\n"
            "A plugin declares the same things and is checked the same way: "
            "[../tutorial-effect.md](../tutorial-effect.md) (examples/user-effect, "
            "`grazing_restitution`: angle-dependent restitution; examples/crater-escape, "
            "`crater_escape`: a rebound threshold). A new built-in effect is its file, one row "
            "of calibration/effects/builtin_effects.def (the checklist is there), its page and "
            "its test case.\n"});
  return out;
}

}  // namespace ricochet::effects
