// libFuzzer target for the impact-set HDF5 reader at the schema level (see fuzz/README.md).
//
// fuzz_impact_h5 mutates the bytes of HDF5 files, and so spends its time in HDF5's own file-format
// parser, where HDF5 1.10 has known crashes (README, "HDF5 findings"). This target instead decodes
// the input bytes into an impact set's *structure* and writes it through the project's HDF5 layer
// (always a well-formed file): which datasets exist under /impacts, their type (float64, int64,
// strings), length and values (NaN, infinities, -0, huge, tiny), their "unit" attribute (known,
// unknown, of the wrong type or missing), the "schema" and "columns" attributes and the comments.
// Every such file is one a buggy or foreign writer could produce, so the reader must refuse it with
// a located InputError or accept a usable set. Properties (as fuzz_impact_h5):
//  1. read_impact_set_h5 returns a set or throws InputError naming the file; anything else is a
//  bug;
//  2. an accepted set survives write_impact_set_h5 then read_impact_set_h5 bit for bit, and its
//     features can be read;
//  3. nothing is left behind: the temporary files are removed after every input.
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "fuzz_common.hpp"
#include "impact/impact_set.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_impact_h5_schema", what, detail);
}

const ricochet::fuzz::TempH5Files& temps() {
  static const ricochet::fuzz::TempH5Files files("ricochet-fuzz-schema");
  return files;
}
void remove_temporaries() {
  temps().remove();
}

// Column names: the schema's (docs/impact-sets.md), extra columns, and invalid or reserved ones.
// Names an HDF5 path cannot hold ("", ".", with '/') only ever appear in the "columns" attribute.
constexpr std::array<const char*, 28> kNames = {"id",
                                                "shape",
                                                "vin_x",
                                                "vin_y",
                                                "win",
                                                "vout_x",
                                                "vout_y",
                                                "wout",
                                                "alpha_in",
                                                "penetration",
                                                "contact_duration",
                                                "operator",
                                                "replicate",
                                                "weight",
                                                "sigma_vin_x",
                                                "sigma_vin_y",
                                                "sigma_vin_w",
                                                "sigma_vout_x",
                                                "sigma_vout_y",
                                                "sigma_vout_w",
                                                "crater_depth",
                                                "speed_in",
                                                "comments",
                                                "vin_x ",
                                                "9lives",
                                                "a,b",
                                                "",
                                                "x/y"};
constexpr std::size_t kRequired = 8;  // the first eight names
constexpr std::array<const char*, 18> kUnits = {"m/s", "cm/s", "mm/s", "rad/s", "deg/s", "rpm",
                                                "m",   "cm",   "mm",   "s",     "ms",    "rad",
                                                "deg", "-",    "",     "m/s ",  "kg",    "furlong"};

bool hdf5_safe(const std::string& name) {
  return !name.empty() && name != "." && name.find('/') == std::string::npos;
}

double pick_double(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 9)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return in.ConsumeBool() ? HUGE_VAL : -HUGE_VAL;
    case 2:
      return -0.0;
    case 3:
      return std::numeric_limits<double>::denorm_min();
    case 4:
      return in.ConsumeBool() ? 1e308 : -1e308;
    default:
      return in.ConsumeFloatingPointInRange<double>(-100.0, 100.0);
  }
}

std::string pick_text(FuzzedDataProvider& in) {
  if (in.ConsumeIntegralInRange<int>(0, 3) == 0) return in.ConsumeRandomLengthString(12);
  static constexpr std::array<const char*, 7> kTexts = {"C01", "cylinder", "triangle", "2",
                                                        "",    "a,b",      "x\"y"};
  return kTexts[in.ConsumeIntegralInRange<std::size_t>(0, kTexts.size() - 1)];
}

// One dataset: type, length and values decided by the input; a unit attribute most of the time.
void write_column(ricochet::h5::File& f, const std::string& name, std::size_t rows,
                  bool text_column, FuzzedDataProvider& in) {
  const std::string path = "/impacts/" + name;
  std::size_t n = rows;
  if (in.ConsumeIntegralInRange<int>(0, 9) == 0) n = in.ConsumeIntegralInRange<std::size_t>(0, 9);
  // The expected type most of the time, the other types sometimes.
  int type = text_column ? 2 : 0;
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) type = in.ConsumeIntegralInRange<int>(0, 2);
  if (type == 2) {
    std::vector<std::string> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(pick_text(in));
    f.write_strings(path, v);
  } else if (type == 1) {
    std::vector<std::int64_t> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(in.ConsumeIntegral<std::int64_t>());
    f.write(path, std::span<const std::int64_t>(v));
  } else {
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(pick_double(in));
    if (in.ConsumeIntegralInRange<int>(0, 15) == 0 && n % 2 == 0 && n > 0)
      f.write(path, v, {n / 2, 2});  // two-dimensional
    else
      f.write(path, v);
  }
  switch (in.ConsumeIntegralInRange<int>(0, 9)) {
    case 0:
      break;  // no unit
    case 1:
      f.set_attr(path, "unit", pick_double(in));
      break;  // a number, not a string
    default:
      f.set_attr(path, "unit",
                 kUnits[in.ConsumeIntegralInRange<std::size_t>(0, kUnits.size() - 1)]);
  }
}

// The unit the schema expects for a required column (so that most sets get past the units).
const char* natural_unit(std::size_t k) {
  return k == 4 || k == 7 ? "rad/s" : "m/s";
}

// Writes the file the input describes. Returns false when the HDF5 layer refuses to write it
// (not a finding: such a file does not exist).
bool write_described_file(const std::string& path, FuzzedDataProvider& in) {
  ricochet::h5::File f(path, ricochet::h5::File::Mode::kTruncate);
  if (in.ConsumeIntegralInRange<int>(0, 31) == 0) return true;  // no /impacts at all
  f.create_group("/impacts");
  switch (in.ConsumeIntegralInRange<int>(0, 15)) {
    case 0:
      break;  // no schema attribute
    case 1:
      f.set_attr("/impacts", "schema", in.ConsumeRandomLengthString(24));
      break;
    case 2:
      f.set_attr("/impacts", "schema", 1.0);
      break;
    default:
      f.set_attr("/impacts", "schema", "ricochet-impact-set-1");
  }
  const std::size_t rows = in.ConsumeIntegralInRange<std::size_t>(0, 6);
  std::vector<std::string> listed;
  // The required columns, each kept most of the time, then extra ones.
  for (std::size_t k = 0; k < kRequired; ++k) {
    if (in.ConsumeIntegralInRange<int>(0, 19) == 0) continue;
    const std::string name = kNames[k];
    if (k < 2) {
      write_column(f, name, rows, true, in);
    } else {
      // Mostly the schema's own unit, so that the values (not the units) are what varies.
      std::vector<double> v;
      for (std::size_t i = 0; i < rows; ++i) v.push_back(pick_double(in));
      if (in.ConsumeIntegralInRange<int>(0, 3) == 0) {
        write_column(f, name, rows, false, in);
      } else {
        f.write("/impacts/" + name, v);
        f.set_attr("/impacts/" + name, "unit", natural_unit(k));
      }
    }
    listed.push_back(name);
  }
  const std::size_t extra = in.ConsumeIntegralInRange<std::size_t>(0, 4);
  for (std::size_t e = 0; e < extra; ++e) {
    const std::string name = kNames[in.ConsumeIntegralInRange<std::size_t>(0, kNames.size() - 1)];
    const bool text = name == "id" || name == "shape" || name == "operator" ||
                      name == "replicate" || name == "comments";
    if (hdf5_safe(name)) write_column(f, name, rows, text, in);
    if (name != "comments") listed.push_back(name);
  }
  // The "columns" attribute: absent (the reader lists the group), exact, or altered.
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      break;
    case 1: {
      std::string text;
      for (const auto& n : listed) text += (text.empty() ? "" : ",") + n;
      if (in.ConsumeBool()) text += "," + in.ConsumeRandomLengthString(8);
      f.set_attr("/impacts", "columns", text);
      break;
    }
    default: {
      std::string text;
      for (const auto& n : listed) text += (text.empty() ? "" : ",") + n;
      f.set_attr("/impacts", "columns", text);
    }
  }
  f.flush();
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(remove_temporaries);
  // HDF5 keeps the blocks of a closed file on its free lists for the next file instead of
  // freeing them: every input opens one to two files, and ASan maps every freed half megabyte
  // afresh (two thirds of the time went to page faults). The reader under test is unchanged.
  H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  struct RemoveAtEnd {
    ~RemoveAtEnd() { remove_temporaries(); }
  } remove_at_end;
  FuzzedDataProvider in(data, size);
  const std::string& path = temps().input;
  try {
    if (!write_described_file(path, in)) return 0;
  } catch (const std::exception&) {
    return 0;  // the HDF5 layer would not write this structure: nothing to read
  }
  ricochet::ImpactSet set;
  try {
    set = ricochet::read_impact_set_h5(path);
  } catch (const ricochet::InputError& e) {
    if (e.file() != path) fail("InputError names the wrong file:", e.what());
    return 0;  // refused with a located message
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  try {
    const std::string& rt = temps().roundtrip;
    ricochet::write_impact_set_h5(set, rt);
    const ricochet::ImpactSet back = ricochet::read_impact_set_h5(rt);
    if (!ricochet::fuzz::same_set(set, back)) fail("round trip changed the set");
    for (const auto& name : set.feature_names()) (void)set.feature(name);
  } catch (const std::exception& e) {
    fail("accepted set fails downstream:", e.what());
  }
  return 0;
}
