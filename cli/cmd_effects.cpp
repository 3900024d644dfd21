// `ricochet effects [NAME]`: the registry of physical effects (docs/commands/effects.md);
// `--markdown`, the catalog page docs/effects/README.md.
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "cli_common.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"
#include "effects/catalog.hpp"
#include "effects/coefficient_law.hpp"
#include "effects/force_term.hpp"
#include "effects/registry.hpp"

namespace ricochet::cli {
namespace {

struct EffectsOptions {
  OutputOptions output;
  std::string name;
  std::vector<std::string> plugins;
  bool markdown = false;
};

nlohmann::json describe(const Effect& e) {
  nlohmann::json j;
  j["name"] = std::string(e.name());
  j["stage"] = std::string(stage_name(e.stage()));
  j["summary"] = std::string(e.summary());
  j["equation"] = std::string(e.equation());
  j["reference"] = std::string(e.reference());
  j["parameters"] = nlohmann::json::array();
  for (const auto& p : e.parameters()) {
    nlohmann::json q = {{"name", std::string(p.name)},
                        {"unit", std::string(p.unit)},
                        {"lower", p.lower},
                        {"upper", p.upper},
                        {"nominal", p.nominal},
                        {"calibrated", p.calibrated},
                        {"description", std::string(p.description)},
                        {"role", std::string(role_name(p.role))},
                        {"identified_by", std::string(identified_by_name(p.identified_by))}};
    q["neutral"] = std::isnan(p.neutral) ? nlohmann::json(nullptr) : nlohmann::json(p.neutral);
    j["parameters"].push_back(q);
  }
  const Signature sig = e.signature();
  j["generated"] = e.generated();
  j["meaning"] = std::string(sig.meaning);
  j["family"] = std::string(family_name(e.kind().family));
  j["variable"] = std::string(variable_name(e.kind().variable));
  j["signature"] = nlohmann::json::array();
  for (const SignatureTrend& t : sig.trends)
    j["signature"].push_back(
        {{"quantity", std::string(t.quantity)}, {"feature", std::string(t.feature)}});
  j["contact_bias"] = sig.contact_bias;
  j["state"] = nlohmann::json::array();
  for (const auto& s : e.state())
    j["state"].push_back({{"name", std::string(s.name)}, {"unit", std::string(s.unit)}});
  return j;
}

// The generated coefficient laws in a few lines: one per coefficient, one per variable.
void print_generated_family(const std::vector<const Effect*>& list) {
  std::size_t total = 0;
  std::map<std::string_view, std::size_t> per_coefficient;
  for (const Effect* e : list)
    if (const auto law = effects::parse_coefficient_law_name(e->name())) {
      ++per_coefficient[law->coefficient];
      ++total;
    }
  std::printf(
      "\nGenerated coefficient laws <coefficient>_<variable>_<form> (%zu effects, stage "
      "coefficient; docs/effects/coefficient_law.md):\n",
      total);
  for (auto c : effects::law_coefficients()) {
    if (!per_coefficient.count(c)) continue;
    const std::string cs(c);
    std::printf(
        "  %-4s %2zu laws  %s_<variable>_linear: c_%s_<tag>, %s_<variable>_power: p_%s_<tag>\n",
        cs.c_str(), per_coefficient[c], cs.c_str(), cs.c_str(), cs.c_str(), cs.c_str());
  }
  std::printf("  %-16s %-6s %-6s %6s %6s\n", "variable", "tag", "unit", "x_ref", "x_hi");
  for (const auto& v : effects::law_variable_info())
    std::printf("  %-16s %-6s %-6s %6g %6g\n", std::string(v.name).c_str(),
                std::string(v.tag).c_str(), std::string(v.unit).c_str(), v.x_ref, v.x_hi);
  std::printf(
      "  linear: C_eff = C (1 + c x), c in [-0.9/x_hi, 3/x_ref]; power: C_eff = C (max(x, 1e-3 "
      "x_ref) / x_ref)^p, p in [-1.5, 1.5];\n  factor clamped to [0.02, 50], neutral at 0. One in "
      "detail: ricochet effects muR_spin_linear\n");
  bool terms = false;
  for (const Effect* e : list) terms = terms || e->name().starts_with("term_");
  if (!terms) return;
  std::printf(
      "\nForce terms term_<name> (%zu effects; docs/effects/force_term.md): the force-residual "
      "discovery's library, one parameter c_<name> each, neutral at 0, c > 0 resists:\n",
      effects::force_terms().size());
  for (const effects::ForceTerm& t : effects::force_terms())
    std::printf("  %-22s %-10s %-18s |c| <= %-9.3g %s\n", std::string(t.name).c_str(),
                std::string(effects::component_name(t.component)).c_str(),
                std::string(t.expression).c_str(), effects::force_term_bound(t),
                std::string(t.unit).c_str());
}

// The --json document: every listed effect described.
nlohmann::json catalog_json(const std::vector<const Effect*>& list) {
  nlohmann::json j = nlohmann::json::array();
  for (const Effect* e : list) j.push_back(describe(*e));
  return {{"effects", j}};
}

// --out FILE.csv: the listed effects' parameters, one row per parameter. Units are the declared SI
// units; an empty neutral has none. (--out FILE.json is the --json document: cli_common.hpp.)
void write_catalog_csv(const std::vector<const Effect*>& list, const std::string& path) {
  CsvTable t;
  t.row({"effect", "stage", "generated", "parameter", "unit", "lower", "upper", "nominal",
         "neutral", "calibrated", "description"});
  const auto number = CsvTable::num;  // a missing bound or neutral (NaN) is an empty cell
  for (const Effect* e : list)
    for (const auto& p : e->parameters())
      t.row({std::string(e->name()), std::string(stage_name(e->stage())),
             e->generated() ? "1" : "0", std::string(p.name), std::string(p.unit), number(p.lower),
             number(p.upper), number(p.nominal), number(p.neutral), p.calibrated ? "1" : "0",
             std::string(p.description)});
  t.write(path);
}

void run(const EffectsOptions& o) {
  require_out_extension(o.output, {".csv"});
  auto& registry = EffectRegistry::global();
  for (const auto& p : o.plugins) {
    try {
      registry.load_plugin(p);
    } catch (const std::exception& e) {
      throw InputError(p, 0, "--plugin", e.what());
    }
  }
  if (o.markdown) {
    if (!o.name.empty())
      throw InputError("<command line>", 0, "--markdown", "lists the whole catalog: drop NAME");
    std::fputs(effects::catalog_markdown(registry).c_str(), stdout);
    return;
  }
  std::vector<const Effect*> list;
  if (o.name.empty()) {
    list = registry.all();
  } else {
    try {
      list.push_back(&registry.get(o.name));
    } catch (const std::exception& e) {
      throw InputError("<command line>", 0, "NAME", e.what());
    }
  }
  if (!o.output.out.empty()) write_catalog_csv(list, o.output.out);
  if (o.output.json) {
    print_json(catalog_json(list));
    return;
  }
  // Without a NAME the generated family is one paragraph, not 40 entries (its JSON lists all).
  std::size_t generated = 0;
  for (const Effect* e : list) {
    if (o.name.empty() && e->generated()) {
      ++generated;
      continue;
    }
    std::printf("%-18s [%s] %s\n", std::string(e->name()).c_str(),
                std::string(stage_name(e->stage())).c_str(), std::string(e->summary()).c_str());
    if (!o.name.empty()) {
      std::printf("  equation : %s\n  reference: %s\n", std::string(e->equation()).c_str(),
                  std::string(e->reference()).c_str());
    }
    for (const auto& p : e->parameters())
      std::printf("    %-8s %-8s [%g, %g] nominal %g%s  %s\n", std::string(p.name).c_str(),
                  std::string(p.unit).c_str(), p.lower, p.upper, p.nominal,
                  std::isnan(p.neutral) ? "" : (", neutral " + std::to_string(p.neutral)).c_str(),
                  std::string(p.description).c_str());
  }
  if (generated > 0) print_generated_family(list);
}

}  // namespace

void add_effects_command(CLI::App& app) {
  auto opts = std::make_shared<EffectsOptions>();
  CLI::App* sub = app.add_subcommand("effects", "List the physical effects a model can compose");
  sub->add_option("NAME", opts->name, "Show one effect in detail");
  sub->add_option("--plugin", opts->plugins, "Load user effects from a shared library");
  add_output_options(sub, opts->output);
  sub->add_flag("--markdown", opts->markdown,
                "Print the catalog as Markdown, the page docs/effects/README.md (with --plugin, "
                "the plugins' effects too)")
      ->excludes("--json")
      ->excludes("--out");
  sub->callback([opts] { run(*opts); });
}

}  // namespace ricochet::cli
