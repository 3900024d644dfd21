// CSV form of the impact-set schema: the embedded lab data, units, and every validation error
// (each must name the file, the 1-based line and the column).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/csv.hpp"
#include "common/error.hpp"
#include "impact/impact_set.hpp"

namespace ricochet {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";
const std::string kHeader =
    "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n";

// Parses `text` expecting an InputError; returns it so the test can check where it points.
std::optional<InputError> parse_error(const std::string& text) {
  try {
    parse_impact_set_csv(text, "bad.csv");
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
}

#define EXPECT_INPUT_ERROR(text, expected_line, expected_field)                     \
  do {                                                                              \
    const auto err = parse_error(text);                                             \
    ASSERT_TRUE(err.has_value()) << "accepted:\n" << (text);                        \
    EXPECT_EQ(err->file(), "bad.csv");                                              \
    EXPECT_EQ(err->line(), static_cast<std::size_t>(expected_line)) << err->what(); \
    EXPECT_EQ(err->field(), (expected_field)) << err->what();                       \
  } while (false)

TEST(ImpactCsv, ReadsLabCylindersInTableOrder) {
  const ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  ASSERT_EQ(set.size(), 28u);
  EXPECT_EQ(set.source, kLab + "cylinders.csv");
  EXPECT_EQ(set.comments.size(), 2u);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const std::string expected = (i < 9 ? "C0" : "C") + std::to_string(i + 1);
    EXPECT_EQ(set.impacts[i].id, expected);
    EXPECT_EQ(set.impacts[i].shape, "cylinder");
    EXPECT_EQ(set.impacts[i].op.value_or(""), "2");
  }
  // First and last rows of paper Table A2.
  const Impact& first = set.impacts.front();
  EXPECT_EQ(first.vin, (Vel3{2.52, -2.65, -68.77}));
  EXPECT_EQ(first.vout, (Vel3{3.32, 0.90, -40.90}));
  const Impact& last = set.impacts.back();
  EXPECT_EQ(last.vin, (Vel3{3.10, -2.22, -66.60}));
  EXPECT_EQ(last.vout, (Vel3{3.26, 0.94, -38.71}));
  EXPECT_TRUE(set.extra_names.empty());
}

TEST(ImpactCsv, ReadsLabTriangles) {
  const ImpactSet set = read_impact_set(kLab + "triangles.csv");
  ASSERT_EQ(set.size(), 31u);
  EXPECT_EQ(set.impacts[17].id, "T18");
  // T18 is the only release with omega_out > 0 (the maximum of Table 2, 2.41 rad/s).
  EXPECT_EQ(set.impacts[17].vout[kW], 2.41);
  for (const auto& m : set.impacts) EXPECT_EQ(m.shape, "triangle");
}

TEST(ImpactCsv, ConvertsUnitsToSi) {
  const std::string text =
      "id,shape,vin_x[cm/s],vin_y[mm/s],win[deg/s],vout_x[m/s],vout_y[m/s],wout[rpm],"
      "alpha_in[deg],penetration[mm],contact_duration[ms],weight[-],crater[cm],"
      "energy_ratio[-]\n"
      "A,cylinder,250,-2000,-180,3,0.5,60,30,12,4.5,2,7,0.25\n";
  const ImpactSet set = parse_impact_set_csv(text, "units.csv");
  ASSERT_EQ(set.size(), 1u);
  const Impact& m = set.impacts[0];
  EXPECT_DOUBLE_EQ(m.vin[kVx], 2.5);
  EXPECT_DOUBLE_EQ(m.vin[kVy], -2.0);
  EXPECT_DOUBLE_EQ(m.vin[kW], -std::numbers::pi);
  EXPECT_DOUBLE_EQ(m.vout[kW], 2 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(*m.alpha_in, std::numbers::pi / 6);
  EXPECT_DOUBLE_EQ(*m.penetration, 0.012);
  EXPECT_DOUBLE_EQ(*m.contact_duration, 0.0045);
  EXPECT_DOUBLE_EQ(*m.weight, 2.0);
  ASSERT_EQ(set.extra_names, (std::vector<std::string>{"crater", "energy_ratio"}));
  EXPECT_EQ(set.extra_units, (std::vector<std::string>{"m", "-"}));
  ASSERT_EQ(m.extra.size(), 2u);
  EXPECT_DOUBLE_EQ(m.extra[0], 0.07);
  EXPECT_DOUBLE_EQ(m.extra[1], 0.25);
  EXPECT_FALSE(m.op.has_value());
  EXPECT_FALSE(m.sigma_vin.has_value());
}

TEST(ImpactCsv, OptionalCellsMayBeEmptyAndSigmaComesAsTriples) {
  const std::string text =
      "# provenance line\n" + std::string("id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],") +
      "vout_x[m/s],vout_y[m/s],wout[rad/s],operator,sigma_vin_x[m/s],sigma_vin_y[m/s],"
      "sigma_vin_w[rad/s],extra1[s]\n"
      "A,cylinder,1,-1,-10,1,0.5,-5,,0.01,0.02,0.3,\n"
      "B,cylinder,1,-1,-10,1,0.5,-5,ops,,,,1.5\n";
  const ImpactSet set = parse_impact_set_csv(text, "opt.csv");
  ASSERT_EQ(set.size(), 2u);
  EXPECT_FALSE(set.impacts[0].op.has_value());
  ASSERT_TRUE(set.impacts[0].sigma_vin.has_value());
  EXPECT_EQ(*set.impacts[0].sigma_vin, (Vel3{0.01, 0.02, 0.3}));
  EXPECT_TRUE(std::isnan(set.impacts[0].extra[0]));
  EXPECT_EQ(set.impacts[1].op.value_or(""), "ops");
  EXPECT_FALSE(set.impacts[1].sigma_vin.has_value());
  EXPECT_EQ(set.impacts[1].extra[0], 1.5);
  EXPECT_EQ(set.comments, (std::vector<std::string>{"provenance line"}));
}

TEST(ImpactCsv, ToleratesCrlfBomBlankLinesQuotesAndCommentsBetweenRows) {
  const std::string text = "\xEF\xBB\xBF# c1\r\n" + std::string("\r\n") +
                           "id , shape , vin_x [m/s],vin_y[m/s],win[rad/s],vout_x[m/s],"
                           "vout_y[m/s],wout[rad/s]\r\n"
                           "\"A,1\", cylinder ,+1.5,-1e0,-10,1,0.5,-5\r\n"
                           "# c2\r\n"
                           "\"say \"\"hi\"\"\",triangle,1,-1,-10,1,0.5,-5\r\n\r\n";
  const ImpactSet set = parse_impact_set_csv(text, "crlf.csv");
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.impacts[0].id, "A,1");
  EXPECT_EQ(set.impacts[0].shape, "cylinder");
  EXPECT_EQ(set.impacts[0].vin[kVx], 1.5);
  EXPECT_EQ(set.impacts[1].id, "say \"hi\"");
  EXPECT_EQ(set.comments, (std::vector<std::string>{"c1", "c2"}));
}

// ---- validation errors: file, line (1-based) and column ------------------------------------

TEST(ImpactCsvErrors, MissingRequiredColumn) {
  EXPECT_INPUT_ERROR(
      "# comment\nid,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],wout[rad/s]\n"
      "A,cylinder,1,-1,-10,1,-5\n",
      2, "vout_y");
  EXPECT_INPUT_ERROR("shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n",
                     1, "id");
}

TEST(ImpactCsvErrors, NonNumericAndEmptyCells) {
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5,-5\nB,cylinder,1,-1,abc,1,0.5,-5\n", 3,
                     "win");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1.5x,-1,-10,1,0.5,-5\n", 2, "vin_x");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,,0.5,-5\n", 2, "vout_x");
  EXPECT_INPUT_ERROR(kHeader + ",cylinder,1,-1,-10,1,0.5,-5\n", 2, "id");
  EXPECT_INPUT_ERROR(kHeader + "A,,1,-1,-10,1,0.5,-5\n", 2, "shape");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5,1e999\n", 2, "wout");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,+-1,-10,1,0.5,-5\n", 2, "vin_y");
}

TEST(ImpactCsvErrors, NanAndInfinity) {
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,nan,-1,-10,1,0.5,-5\n", 2, "vin_x");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5,NaN\n", 2, "wout");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-inf,-10,1,0.5,-5\n", 2, "vin_y");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,infinity,1,0.5,-5\n", 2, "win");
}

TEST(ImpactCsvErrors, VerticalVelocitySigns) {
  // vin_y must be < 0 (falling), vout_y > 0 (rebounding); zero is refused on both.
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,0.2,-10,1,0.5,-5\n", 2, "vin_y");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,0,-10,1,0.5,-5\n", 2, "vin_y");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5,-5\nB,cylinder,1,-1,-10,1,-0.5,-5\n", 3,
                     "vout_y");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0,-5\n", 2, "vout_y");
}

TEST(ImpactCsvErrors, DuplicateId) {
  const auto err = parse_error(kHeader + "A,cylinder,1,-1,-10,1,0.5,-5\n# note\n" +
                               "B,cylinder,1,-1,-10,1,0.5,-5\nA,cylinder,1,-1,-10,1,0.5,-5\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 5u);
  EXPECT_EQ(err->field(), "id");
  EXPECT_NE(err->detail().find("line 2"), std::string::npos) << err->detail();
}

TEST(ImpactCsvErrors, WrongCellCount) {
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5\n", 2, "wout");
  EXPECT_INPUT_ERROR(kHeader + "A,cylinder,1,-1,-10,1,0.5,-5,7\n", 2, "column 9");
}

TEST(ImpactCsvErrors, UnknownUnitNamesHeaderLineAndColumn) {
  const auto err = parse_error(
      "# a\n# b\nid,shape,vin_x[km/h],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(err->line(), 3u);
  EXPECT_EQ(err->field(), "vin_x");
  EXPECT_NE(err->detail().find("km/h"), std::string::npos);
  // An unknown unit on an extra column is refused too.
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],crater[in]\n",
      1, "crater");
}

TEST(ImpactCsvErrors, HeaderProblems) {
  // A unit of the wrong dimension.
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[m/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n", 1, "win");
  // A numeric column without a unit, an extra column without a unit.
  EXPECT_INPUT_ERROR("id,shape,vin_x,vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n",
                     1, "vin_x");
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],notes\n", 1,
      "notes");
  // A unit on a text column, a duplicated column, a malformed cell, a reserved name.
  EXPECT_INPUT_ERROR(
      "id[-],shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n", 1,
      "id");
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],vin_x[m/s]\n",
      1, "vin_x");
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s]x,vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n", 1,
      "vin_x");
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],speed_in[m/s]"
      "\n",
      1, "speed_in");
  EXPECT_INPUT_ERROR(
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],\n", 1,
      "column 9");
  // Only some components of an uncertainty.
  EXPECT_INPUT_ERROR(kHeader.substr(0, kHeader.size() - 1) + ",sigma_vout_x[m/s]\n", 1,
                     "sigma_vout_y");
}

TEST(ImpactCsvErrors, NoHeaderAtAll) {
  for (const std::string text : {"", "# only a comment\n", "\n\n  \n"}) {
    const auto err = parse_error(text);
    ASSERT_TRUE(err) << text;
    EXPECT_EQ(err->field(), "header");
  }
}

TEST(ImpactCsvErrors, OptionalValuesOutOfRange) {
  const std::string h = kHeader.substr(0, kHeader.size() - 1);
  EXPECT_INPUT_ERROR(h + ",weight[-]\nA,cylinder,1,-1,-10,1,0.5,-5,-1\n", 2, "weight");
  EXPECT_INPUT_ERROR(h + ",penetration[m]\nA,cylinder,1,-1,-10,1,0.5,-5,-0.01\n", 2, "penetration");
  EXPECT_INPUT_ERROR(h + ",sigma_vin_x[m/s],sigma_vin_y[m/s],sigma_vin_w[rad/s]\n" +
                         "A,cylinder,1,-1,-10,1,0.5,-5,0.1,,0.2\n",
                     2, "sigma_vin_y");
  EXPECT_INPUT_ERROR(h + ",sigma_vin_x[m/s],sigma_vin_y[m/s],sigma_vin_w[rad/s]\n" +
                         "A,cylinder,1,-1,-10,1,0.5,-5,0.1,0.1,-0.2\n",
                     2, "sigma_vin_w");
}

TEST(ImpactCsvErrors, QuotesAndControlCharacters) {
  EXPECT_INPUT_ERROR(kHeader + "\"A,cylinder,1,-1,-10,1,0.5,-5\n", 2, "id");
  EXPECT_INPUT_ERROR(kHeader + "\"A\"x,cylinder,1,-1,-10,1,0.5,-5\n", 2, "id");
  EXPECT_INPUT_ERROR(kHeader + "A,\"cyl\tinder\",1,-1,-10,1,0.5,-5\n", 2, "shape");
}

TEST(ImpactCsvErrors, MessageReadsFileLineField) {
  const auto err = parse_error(kHeader + "A,cylinder,1,0.2,-10,1,0.5,-5\n");
  ASSERT_TRUE(err);
  EXPECT_EQ(std::string(err->what()).rfind("bad.csv:2: field 'vin_y': ", 0), 0u) << err->what();
}

TEST(ImpactCsvErrors, MissingFile) {
  try {
    read_impact_set("/nonexistent/dir/impacts.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/dir/impacts.csv");
  }
  EXPECT_THROW(read_impact_set(kLab + "cylinders.txt"), InputError);
}

// ---- writer ---------------------------------------------------------------------------------

TEST(ImpactCsvWriter, WritesSiUnitsOptionalColumnsOnlyWhenUsedAndReadsBack) {
  ImpactSet set = read_impact_set(kLab + "triangles.csv");
  const std::string text = format_impact_set_csv(set);
  // Comments first, then the header with units, then one row per release.
  EXPECT_EQ(text.rfind("# Ricochet impact set v1.", 0), 0u);
  EXPECT_NE(text.find("\nid,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],"
                      "wout[rad/s],operator\n"),
            std::string::npos);
  EXPECT_EQ(text.find("alpha_in"), std::string::npos);
  EXPECT_NE(text.find("\nT18,triangle,2.3,-1.95,-14.5,0.24,0.18,2.41,2\n"), std::string::npos);
  const ImpactSet back = parse_impact_set_csv(text, "back.csv");
  ASSERT_EQ(back.size(), set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    EXPECT_EQ(back.impacts[i].vin, set.impacts[i].vin);
    EXPECT_EQ(back.impacts[i].vout, set.impacts[i].vout);
  }
  EXPECT_EQ(format_impact_set_csv(back), text);
}

TEST(ImpactCsvWriter, QuotesTextThatWouldNotReadBack) {
  ImpactSet set;
  set.source = "memory";
  for (const std::string id : {"#1", " padded ", "a,b", "q\"q"}) {
    Impact m;
    m.id = id;
    m.shape = "cylinder";
    m.vin = {1, -1, -10};
    m.vout = {1, 0.5, -5};
    set.impacts.push_back(m);
  }
  const ImpactSet back = parse_impact_set_csv(format_impact_set_csv(set), "q.csv");
  ASSERT_EQ(back.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(back.impacts[i].id, set.impacts[i].id);
}

TEST(ImpactValidate, InMemoryChecksName) {
  ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  EXPECT_NO_THROW(validate(set));
  set.impacts[4].vout[kVy] = -0.1;
  try {
    validate(set);
    FAIL() << "accepted vout_y < 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 5u);  // row index + 1
    EXPECT_EQ(e.field(), "vout_y");
  }
  set.impacts[4].vout[kVy] = 0.5;
  set.impacts[6].id = "C01";
  EXPECT_THROW(validate(set), InputError);
  set.impacts[6].id = "C07";
  set.extra_names = {"bad name"};
  set.extra_units = {"m"};
  EXPECT_THROW(validate(set), InputError);
  // Writers refuse what readers would refuse.
  set.extra_names.clear();
  set.extra_units.clear();
  set.impacts[0].vin[kVx] = std::nan("");
  EXPECT_THROW(format_impact_set_csv(set), InputError);
}

TEST(ImpactFeatures, NamesValuesAndShapes) {
  ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  const auto speed = set.feature("speed_in");
  ASSERT_EQ(speed.size(), 28u);
  EXPECT_DOUBLE_EQ(speed[0], std::sqrt(2.52 * 2.52 + 2.65 * 2.65));
  EXPECT_EQ(set.feature("wout")[23], -77.82);
  EXPECT_TRUE(std::isnan(set.feature("penetration")[0]));
  EXPECT_THROW(set.feature("vinx"), std::invalid_argument);
  try {
    set.feature("vinx");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vin_x"), std::string::npos);  // lists known names
  }
  const auto names = set.feature_names();
  EXPECT_EQ(names, (std::vector<std::string>{"vin_x", "vin_y", "win", "vout_x", "vout_y", "wout",
                                             "speed_in"}));
  ImpactSet both = set;
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  both.impacts.insert(both.impacts.end(), tri.impacts.begin(), tri.impacts.end());
  EXPECT_EQ(both.with_shape("triangle").size(), 31u);
  EXPECT_EQ(both.with_shape("cylinder").size(), 28u);
  EXPECT_EQ(both.with_shape("").size(), 59u);
}

// The one CSV cell writer (common/csv.hpp): every text the writer quotes, the reader returns
// unchanged, in an id cell of a real set.
TEST(CsvCell, QuotesExactlyWhatTheReaderWouldAlter) {
  EXPECT_EQ(csv_cell("C01"), "C01");
  EXPECT_EQ(csv_cell(""), "");
  EXPECT_EQ(csv_cell("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_cell("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_cell("#1"), "\"#1\"");
  EXPECT_EQ(csv_cell(" padded "), "\" padded \"");
  EXPECT_EQ(csv_cell("in#side"), "in#side");
  const std::vector<std::string> row = {"a", "b,c", ""};
  EXPECT_EQ(csv_row(row), "a,\"b,c\",");
  for (const std::string id : {"a,b", "say \"hi\"", "#1", " padded ", " a, \"b\" "}) {
    const std::string text =
        "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s]\n" +
        csv_cell(id) + ",cylinder,2.9,-2.3,-65,3,0.8,-40\n";
    const ImpactSet set = parse_impact_set_csv(text, "cells.csv");
    ASSERT_EQ(set.size(), 1u);
    EXPECT_EQ(set.impacts[0].id, id);
  }
}

}  // namespace
}  // namespace ricochet
