// libFuzzer target for the campaign design reader, dem::parse_campaign_design (see
// fuzz/README.md). The design is read against the project's decks (liggghts-inputs/), as if it
// were a file of liggghts-inputs/campaigns/, so that incident_from = "../../data/lab/..." works.
//
// Properties checked on every input:
//  1. the reader either returns a design or throws InputError naming a file (the design, or the
//     impact set it refers to); any other exception, crash, leak, hang or sanitizer report is a
//     bug;
//  2. an accepted design is one a campaign can run: at least one impact, unique ids, finite
//     incident states with vy < 0, finite angles, ranks_per_impact >= 1, fps finite and >= 0.
// There is no design writer, so there is no round trip to check.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <set>
#include <string>

#include "campaign_design.hpp"
#include "common/error.hpp"
#include "fuzz_common.hpp"
#include "params.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_campaign_toml", what, detail);
}

const std::string kPath = RICOCHET_LIGGGHTS_INPUTS "/campaigns/fuzz-input.toml";

const ricochet::dem::Decks& decks() {
  static const ricochet::dem::Decks d = ricochet::dem::Decks::locate(RICOCHET_LIGGGHTS_INPUTS);
  return d;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)decks();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ricochet::dem::CampaignDesign d;
  try {
    d = ricochet::dem::parse_campaign_design(text, kPath, decks());
  } catch (const ricochet::InputError& e) {
    if (e.file().empty()) fail("InputError names no file:", e.what());
    return 0;
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  if (d.impacts.empty()) fail("accepted a design without impacts");
  if (d.ranks_per_impact < 1) fail("accepted ranks_per_impact < 1");
  if (!std::isfinite(d.extract.fps) || d.extract.fps < 0) fail("accepted a bad extract.fps");
  std::set<std::string> ids;
  for (const auto& s : d.impacts) {
    if (!ids.insert(s.id).second) fail("duplicate id:", s.id);
    for (double v : s.vin)
      if (!std::isfinite(v)) fail("accepted a non-finite incident state:", s.id);
    if (!(s.vin[1] < 0)) fail("accepted an incident vy >= 0:", s.id);
    if (!std::isfinite(s.alpha_in_rad)) fail("accepted a non-finite angle:", s.id);
  }
  return 0;
}
