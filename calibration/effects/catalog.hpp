// The effect catalog as a document: docs/effects/README.md is this function's output for the
// built-in registry (`ricochet effects --markdown`), written from the effects' own declarations
// so that the page cannot drift from the code (tests/engine/effects_test.cpp compares them).
#pragma once

#include <string>

#include "effects/registry.hpp"

namespace ricochet::effects {

/// Markdown of the catalog of `registry`: one table row per hand-written effect (name, stage,
/// kind, parameters with unit, role and what identifies them, signature trends, a link to
/// docs/effects/<name>.md), one paragraph for the generated coefficient laws, and the words of
/// the vocabularies an effect declares in (parameter roles, what identifies a parameter,
/// signature quantities and features). Ends with a newline.
std::string catalog_markdown(const EffectRegistry& registry);

}  // namespace ricochet::effects
