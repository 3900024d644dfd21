// libFuzzer target for the track reader, read_block_track (impact/block_track.hpp), at the schema
// level (see fuzz/README.md), like fuzz_impact_h5_schema: the input bytes decide the structure of
// /dem/tracks/ID, written through the project's HDF5 layer (always a well-formed file): the
// dataset's rank, shape and values (NaN, infinities, -0, huge), its `columns` attribute (the
// known names with their SI unit, another unit, no unit, unknown names, repeats, empty entries; a
// number instead of text; missing) and its `block_mass_kg` attribute (a number, text, missing).
// Properties:
//  1. read_block_track returns a track or throws InputError naming the file and the track;
//     anything else is a bug;
//  2. an accepted track has a t column and every column as long as t after pad();
//  3. it survives write_block_track then read_block_track bit for bit (the seventeen columns and
//     the block mass);
//  4. nothing is left behind: the temporary files are removed after every input.
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "fuzz_common.hpp"
#include "impact/block_track.hpp"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail = {}) {
  ricochet::fuzz::fail("fuzz_block_track", what, detail);
}

const ricochet::fuzz::TempH5Files& temps() {
  static const ricochet::fuzz::TempH5Files files("ricochet-fuzz-track");
  return files;
}
void remove_temporaries() {
  temps().remove();
}

constexpr const char* kId = "T01";
constexpr std::array<const char*, 9> kOtherNames = {"t[ms]", "x[mm]",   "fcx[kN]", "torque",
                                                     "speed", "t",       "",        " y[m]",
                                                     "w[rad/s] "};

double pick_double(FuzzedDataProvider& in) {
  switch (in.ConsumeIntegralInRange<int>(0, 9)) {
    case 0:
      return std::numeric_limits<double>::quiet_NaN();
    case 1:
      return in.ConsumeBool() ? HUGE_VAL : -HUGE_VAL;
    case 2:
      return -0.0;
    case 3:
      return in.ConsumeBool() ? 1e308 : -1e308;
    default:
      return in.ConsumeFloatingPointInRange<double>(-100.0, 100.0);
  }
}

// The `columns` entries: mostly the known names with their SI units, sometimes without a unit,
// an unknown or malformed name; in an order and with repeats the input decides.
std::vector<std::string> pick_columns(FuzzedDataProvider& in) {
  const auto& known = ricochet::BlockTrack::column_names();
  std::vector<std::string> cols;
  const std::size_t k = in.ConsumeIntegralInRange<std::size_t>(0, 16);
  for (std::size_t i = 0; i < k; ++i) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
      case 0:
        cols.push_back(kOtherNames[in.ConsumeIntegralInRange<std::size_t>(0, kOtherNames.size() - 1)]);
        break;
      case 1: {
        const std::string n = known[in.ConsumeIntegralInRange<std::size_t>(0, known.size() - 1)];
        cols.push_back(n.substr(0, n.find('[')));  // the name without its unit
        break;
      }
      case 2:
        cols.push_back(in.ConsumeRandomLengthString(10));
        break;
      default:
        cols.push_back(known[in.ConsumeIntegralInRange<std::size_t>(0, known.size() - 1)]);
    }
  }
  return cols;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

// Writes the track the input describes; false when the input is used up before it is described.
bool write_described_file(const std::string& path, FuzzedDataProvider& in) {
  ricochet::h5::File f(path, ricochet::h5::File::Mode::kTruncate);
  const std::string field = std::string(ricochet::kTracksGroup) + "/" + kId;
  const std::vector<std::string> columns = pick_columns(in);
  std::size_t ncols = columns.size();
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) ncols = in.ConsumeIntegralInRange<std::size_t>(0, 16);
  const std::size_t rows = in.ConsumeIntegralInRange<std::size_t>(0, 40);
  std::vector<double> data(rows * ncols);
  for (double& v : data) v = pick_double(in);
  if (in.remaining_bytes() == 0) return false;
  const int rank = in.ConsumeIntegralInRange<int>(0, 5);
  if (rank == 0)
    f.write(field, data);  // one dimension
  else
    f.write(field, data, {rows, ncols});
  switch (in.ConsumeIntegralInRange<int>(0, 5)) {
    case 0:
      break;  // no `columns`: the first campaigns' twelve columns
    case 1:
      f.set_attr(field, "columns", pick_double(in));  // of the wrong type
      break;
    default:
      f.set_attr(field, "columns", joined(columns));
  }
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
      f.set_attr(field, "block_mass_kg", pick_double(in));
      break;
    case 1:
      f.set_attr(field, "block_mass_kg", std::string("2.9"));  // text
      break;
    default:
      break;
  }
  f.flush();
  return true;
}

bool same_track(const ricochet::BlockTrack& a, const ricochet::BlockTrack& b) {
  using ricochet::fuzz::same;
  if (!same(a.block_mass_kg, b.block_mass_kg) || a.size() != b.size()) return false;
  for (const auto& name : ricochet::BlockTrack::column_names()) {
    const auto* x = a.column(name);
    const auto* y = b.column(name);
    if (x->size() != y->size()) return false;
    for (std::size_t i = 0; i < x->size(); ++i)
      if (!same((*x)[i], (*y)[i])) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(remove_temporaries);
  H5set_free_list_limits(-1, -1, -1, -1, -1, -1);  // as fuzz_impact_h5_schema: no page faults
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
  const std::string field = std::string(ricochet::kTracksGroup) + "/" + kId;
  ricochet::BlockTrack track;
  try {
    track = ricochet::read_block_track(path, kId);
  } catch (const ricochet::InputError& e) {
    if (e.file() != path) fail("InputError names the wrong file:", e.what());
    if (e.field() != field) fail("InputError names the wrong track:", e.what());
    return 0;  // refused with a located message
  } catch (const std::exception& e) {
    fail("unexpected exception:", e.what());
  }
  track.pad();
  for (const auto& name : ricochet::BlockTrack::column_names())
    if (track.column(name)->size() != track.size()) fail("a column is not as long as t:", name);
  if (track.size() == 0) return 0;  // nothing to write back (write_block_track refuses it)
  try {
    const std::string& rt = temps().roundtrip;
    ricochet::write_block_track(rt, kId, track);
    const ricochet::BlockTrack back = ricochet::read_block_track(rt, kId);
    if (!same_track(track, back)) fail("round trip changed the track");
  } catch (const std::exception& e) {
    fail("accepted track fails downstream:", e.what());
  }
  return 0;
}
