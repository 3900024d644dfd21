// HDF5 form of the impact-set schema and the CSV -> HDF5 -> CSV round trip, through real files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "impact/impact_set.hpp"
#include "support/temp_dir_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

// A fresh directory per test, removed afterwards.
class ImpactH5 : public test::TempDirTest {
 protected:
  ImpactH5() : TempDirTest("ricochet-impact") {}
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same_sets(const ImpactSet& a, const ImpactSet& b) {
  EXPECT_EQ(a.comments, b.comments);
  EXPECT_EQ(a.extra_names, b.extra_names);
  EXPECT_EQ(a.extra_units, b.extra_units);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Impact& x = a.impacts[i];
    const Impact& y = b.impacts[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.shape, y.shape);
    EXPECT_EQ(x.op, y.op);
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(same_bits(x.vin[c], y.vin[c])) << x.id;
      EXPECT_TRUE(same_bits(x.vout[c], y.vout[c])) << x.id;
    }
    EXPECT_EQ(x.alpha_in, y.alpha_in);
    EXPECT_EQ(x.penetration, y.penetration);
    EXPECT_EQ(x.contact_duration, y.contact_duration);
    EXPECT_EQ(x.weight, y.weight);
    EXPECT_EQ(x.sigma_vin, y.sigma_vin);
    EXPECT_EQ(x.sigma_vout, y.sigma_vout);
    ASSERT_EQ(x.extra.size(), y.extra.size());
    for (std::size_t k = 0; k < x.extra.size(); ++k)
      EXPECT_TRUE(same_bits(x.extra[k], y.extra[k]) ||
                  (std::isnan(x.extra[k]) && std::isnan(y.extra[k])));
  }
}

// A CSV using every optional column, non-SI units, extras and a missing optional value.
const std::string kFullCsv =
    "# synthetic set for the round trip\n"
    "# second provenance line, with a comma, and \"quotes\"\n"
    "id,shape,vin_x[cm/s],vin_y[m/s],win[deg/s],vout_x[m/s],vout_y[m/s],wout[rpm],"
    "alpha_in[deg],penetration[mm],contact_duration[ms],operator,weight[-],"
    "sigma_vin_x[m/s],sigma_vin_y[m/s],sigma_vin_w[rad/s],"
    "sigma_vout_x[m/s],sigma_vout_y[m/s],sigma_vout_w[rad/s],crater_width[cm],energy[-]\n"
    "S1,cylinder,287.3,-2.34,-3725.9,3.055,0.857,-403.9,0,12.5,4.1,op A,1,"
    "0.01,0.01,0.2,0.02,0.02,0.3,7.25,0.1\n"
    "\"S,2\",triangle,375.6,-2.73,-2274.6,2.637,0.509,-165.4,33.3,,3.7,,0.5,"
    ",,,0.03,0.03,0.5,,0.3\n"
    "S3,\"tri angle\",299,-1e-3,-1.7e3,1e-5,7e-1,0.001,-12,0,0.1,op B,2,"
    "0.1,0.2,0.3,,,,1,\n";

TEST_F(ImpactH5, CsvToH5ToCsvIsExact) {
  std::ofstream(path("full.csv")) << kFullCsv;
  const ImpactSet a = read_impact_set(path("full.csv"));
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(a.extra_names.size(), 2u);

  write_impact_set(a, path("full.h5"));
  const ImpactSet b = read_impact_set(path("full.h5"));
  EXPECT_EQ(b.source, path("full.h5"));
  expect_same_sets(a, b);

  write_impact_set(a, path("a.csv"));
  write_impact_set(b, path("b.csv"));
  const std::string text_a = slurp(path("a.csv"));
  EXPECT_FALSE(text_a.empty());
  EXPECT_EQ(text_a, slurp(path("b.csv")));
  // The written CSV is in SI units and reads back to the same values, bit for bit.
  EXPECT_NE(text_a.find("vin_x[m/s]"), std::string::npos);
  EXPECT_NE(text_a.find("wout[rad/s]"), std::string::npos);
  EXPECT_NE(text_a.find("crater_width[m]"), std::string::npos);
  expect_same_sets(a, read_impact_set(path("a.csv")));
}

TEST_F(ImpactH5, LabDataRoundTrip) {
  for (const char* name : {"cylinders", "triangles"}) {
    const ImpactSet a = read_impact_set(kLab + name + ".csv");
    const std::string h5 = path(std::string(name) + ".h5");
    write_impact_set_h5(a, h5);
    const ImpactSet b = read_impact_set_h5(h5);
    expect_same_sets(a, b);
    EXPECT_EQ(format_impact_set_csv(a), format_impact_set_csv(b));
  }
}

TEST_F(ImpactH5, LayoutIsDocumented) {
  const ImpactSet a = read_impact_set(kLab + "cylinders.csv");
  write_impact_set(a, path("c.hdf5"));
  h5::File f(path("c.hdf5"), h5::File::Mode::kRead);
  EXPECT_EQ(f.attr_string("/impacts", "schema"), "ricochet-impact-set-1");
  EXPECT_EQ(f.attr_string("/impacts/vin_x", "unit"), "m/s");
  EXPECT_EQ(f.attr_string("/impacts/wout", "unit"), "rad/s");
  EXPECT_EQ(f.read_strings("/impacts/id").front(), "C01");
  EXPECT_EQ(f.read_doubles("/impacts/vin_y").back(), -2.22);
  EXPECT_EQ(f.read_strings("/impacts/comments").size(), 2u);
  EXPECT_FALSE(f.exists("/impacts/alpha_in"));  // optional columns only when used
}

TEST_F(ImpactH5, ReplacingTheGroupKeepsOtherGroups) {
  const std::string file = path("results.h5");
  {
    h5::File f(file, h5::File::Mode::kTruncate);
    const std::vector<double> v = {1, 2, 3};
    f.write("/other/values", v);
  }
  write_impact_set_h5(read_impact_set(kLab + "triangles.csv"), file);
  write_impact_set_h5(read_impact_set(kLab + "cylinders.csv"), file);
  EXPECT_EQ(read_impact_set(file).size(), 28u);
  h5::File f(file, h5::File::Mode::kRead);
  EXPECT_EQ(f.read_doubles("/other/values").size(), 3u);
}

// Writes the cylinders, lets `corrupt` damage the file, and returns the reader's error.
template <typename Corrupt>
std::optional<InputError> corrupted_error(const std::string& file, Corrupt corrupt) {
  write_impact_set_h5(read_impact_set(kLab + "cylinders.csv"), file);
  {
    h5::File f(file, h5::File::Mode::kReadWrite);
    corrupt(f);
  }
  try {
    read_impact_set_h5(file);
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

TEST_F(ImpactH5, ErrorsNameFileDatasetAndRow) {
  const std::string file = path("bad.h5");
  auto check = [&](auto corrupt, std::size_t line, const std::string& field) {
    const auto err = corrupted_error(file, corrupt);
    ASSERT_TRUE(err.has_value()) << field;
    EXPECT_EQ(err->file(), file);
    EXPECT_EQ(err->line(), line) << err->what();
    EXPECT_EQ(err->field(), field) << err->what();
  };
  auto set_value = [](const char* name, std::size_t row, double value) {
    return [=](h5::File& f) {
      const std::string d = std::string("/impacts/") + name;
      auto v = f.read_doubles(d);
      const auto unit = f.attr_string(d, "unit");
      v[row] = value;
      f.write(d, v);
      f.set_attr(d, "unit", unit);
    };
  };
  check(set_value("vin_y", 2, 0.3), 3, "vin_y");
  check(set_value("vout_y", 0, -0.1), 1, "vout_y");
  check(set_value("win", 27, std::nan("")), 28, "win");
  check(set_value("wout", 5, INFINITY), 6, "wout");
  check(
      [](h5::File& f) {
        auto ids = f.read_strings("/impacts/id");
        ids[9] = "C02";
        f.write_strings("/impacts/id", ids);
      },
      10, "id");
  check([](h5::File& f) { f.set_attr("/impacts/win", "unit", "rad/min"); }, 0, "win");
  check([](h5::File& f) { f.set_attr("/impacts/vin_x", "unit", "rad/s"); }, 0, "vin_x");
  check(
      [](h5::File& f) {
        const auto v = f.read_doubles("/impacts/vout_x");
        f.write("/impacts/vout_x", v);  // rewritten without its unit attribute
      },
      0, "vout_x");
  check(
      [](h5::File& f) {
        std::vector<double> v(27, 1.0);
        f.write("/impacts/vout_x", v);
        f.set_attr("/impacts/vout_x", "unit", "m/s");
      },
      0, "vout_x");
  check(
      [](h5::File& f) {
        f.remove("/impacts/vout_y");
        f.set_attr("/impacts", "columns", "id,shape,vin_x,vin_y,win,vout_x,wout,operator");
      },
      0, "vout_y");
  check([](h5::File& f) { f.set_attr("/impacts", "schema", "something-else"); }, 0, "schema");
}

TEST_F(ImpactH5, NotAnImpactSet) {
  std::ofstream(path("text.h5")) << "not hdf5";
  EXPECT_THROW(read_impact_set(path("text.h5")), InputError);
  { h5::File f(path("empty.h5"), h5::File::Mode::kTruncate); }
  try {
    read_impact_set(path("empty.h5"));
    FAIL() << "accepted a file without /impacts";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "impacts");
  }
}

// Found by fuzz/fuzz_impact_h5: two damaged bytes in the object header of /impacts (the link
// exists, the object does not open) made the HDF5 layer's std::runtime_error escape the reader.
// It is an InputError naming the file and what was being read.
TEST_F(ImpactH5, DamagedObjectHeaderIsAnInputError) {
  const std::string file =
      std::string(RICOCHET_SOURCE_DIR) + "/fuzz/corpus-impact_h5/regress_damaged_object_header.h5";
  try {
    read_impact_set(file);
    FAIL() << "accepted a damaged file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.field(), "schema");
    EXPECT_NE(e.detail().find("damaged HDF5 file"), std::string::npos) << e.what();
  }
}

// Found by fuzz/fuzz_impact_h5 (LeakSanitizer): a string dataset whose read fails part way lost
// the strings HDF5 had already allocated. The reader now owns that memory (h5.cpp, VlenArena); the
// file is an InputError naming the column (the leak itself shows only under the fuzz target).
TEST_F(ImpactH5, PartlyUnreadableStringColumnIsAnInputError) {
  const std::string file =
      std::string(RICOCHET_SOURCE_DIR) + "/fuzz/corpus-impact_h5/regress_partial_string_read.h5";
  try {
    read_impact_set(file);
    FAIL() << "accepted a damaged file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_FALSE(e.field().empty()) << e.what();
  }
}

}  // namespace
}  // namespace ricochet
