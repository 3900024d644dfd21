// libFuzzer target for the model TOML reader, Model::from_toml_string (see fuzz/README.md).
//
// Properties checked on every input:
//  1. the reader either returns a model or throws InputError naming the file; any other
//     exception, crash, leak, hang or sanitizer report is a bug;
//  2. an accepted model has its values and calibration bounds within the declared bounds;
//  3. it survives its own writer: to_toml -> from_toml_string gives the same effects (in order),
//     values and bounds (bit for bit), calibrated and held sets, and writing it again gives the
//     same text.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "common/error.hpp"
#include "effects/model.hpp"
#include "fuzz_common.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_model_toml", what, detail);
}

bool same_model(const ricochet::Model& a, const ricochet::Model& b) {
  using ricochet::fuzz::same;
  if (a.effect_names() != b.effect_names() || a.parameter_count() != b.parameter_count())
    return false;
  for (std::size_t i = 0; i < a.parameter_count(); ++i)
    if (!same(a.values()[i], b.values()[i]) || !same(a.lower(i), b.lower(i)) ||
        !same(a.upper(i), b.upper(i)) || a.calibrated(i) != b.calibrated(i) ||
        a.held(i) != b.held(i))
      return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ricochet::Model model;
  try {
    model = ricochet::Model::from_toml_string(text, "fuzz-model.toml");
  } catch (const ricochet::InputError& e) {
    if (e.file() != "fuzz-model.toml") fail("InputError names the wrong file:", e.what());
    return 0;
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  for (std::size_t i = 0; i < model.parameter_count(); ++i) {
    const auto& spec = model.spec(i);
    const double v = model.values()[i];
    if (!(spec.lower <= v && v <= spec.upper && spec.lower <= model.lower(i) &&
          model.lower(i) <= model.upper(i) && model.upper(i) <= spec.upper))
      fail("accepted value outside its bounds:", std::string(spec.name));
  }
  try {
    const std::string once = model.to_toml();
    const ricochet::Model back = ricochet::Model::from_toml_string(once, "fuzz-roundtrip.toml");
    if (!same_model(model, back)) fail("round trip changed the model:\n", once);
    if (back.to_toml() != once) fail("writer is not stable:\n", once);
    (void)model.to_json().dump();
  } catch (const std::exception& e) {
    fail("accepted model fails downstream:", e.what());
  }
  return 0;
}
