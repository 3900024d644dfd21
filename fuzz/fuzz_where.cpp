// libFuzzer target for the `--where` filter expressions (see fuzz/README.md).
//
// The input is the expression; it filters a fixed set with every kind of column (text columns
// with and without values, optional numbers with gaps, an extra column). Properties:
//  1. filter either returns a set or throws InputError naming "--where" as the file and the
//     offending term as the field; anything else (other exception, crash, leak, hang, sanitizer
//     report) is a bug;
//  2. an accepted filter keeps a subsequence of the releases, in order, and is idempotent:
//     filtering the result again keeps all of it.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "common/error.hpp"
#include "fuzz_common.hpp"
#include "impact/impact_set.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_where", what, detail);
}

const ricochet::ImpactSet& fixed_set() {
  static const ricochet::ImpactSet set = ricochet::parse_impact_set_csv(
      "# a set with every kind of column, for the --where fuzz target\n"
      "id,shape,operator,replicate,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],"
      "wout[rad/s],alpha_in[deg],penetration[mm],contact_duration[ms],weight[-],crater[m]\n"
      "C01,cylinder,ab,r1,2.9,-2.3,-65,1.2,0.8,-20,,12,8,1,0.1\n"
      "C02,cylinder,,r1,3.6,-2.0,-40,1.5,0.6,-25,10,,9,2,\n"
      "T01,triangle,cd,,2.1,-2.8,-10,0.9,1.1,5,-30,20,,0.5,0.3\n"
      "T02,\"tri,angle\",\"a b\",,4.0,-1.5,0,2.0,0.2,-12.5,45,3,12,,0\n",
      "fuzz-where-set.csv");
  return set;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string where(reinterpret_cast<const char*>(data), size);
  const ricochet::ImpactSet& set = fixed_set();
  ricochet::ImpactSet out;
  try {
    out = ricochet::filter(set, where);
  } catch (const ricochet::InputError& e) {
    if (e.file() != "--where") fail("InputError names the wrong file:", e.what());
    if (e.field().empty()) fail("InputError names no term:", e.what());
    return 0;
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  std::size_t j = 0;
  for (const auto& kept : out.impacts) {
    while (j < set.size() && set.impacts[j].id != kept.id) ++j;
    if (j == set.size()) fail("filter invented or reordered a release:", kept.id);
    ++j;
  }
  try {
    const ricochet::ImpactSet again = ricochet::filter(out, where);
    if (again.size() != out.size()) fail("filter is not idempotent:", where);
  } catch (const std::exception& e) {
    fail("filter refuses its own result:", e.what());
  }
  return 0;
}
