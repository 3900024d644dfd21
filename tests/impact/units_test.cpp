// The one unit table (common/units.hpp) shared by the impact-set and track readers: names,
// dimensions, factors to SI, and the lists the error messages print.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "common/error.hpp"
#include "common/units.hpp"
#include "kinematics/reconstruct.hpp"

namespace ricochet {
namespace {

using units::Dim;

TEST(Units, FactorsToSi) {
  struct Case {
    const char* name;
    Dim dim;
    double to_si;
  };
  const double deg = std::numbers::pi / 180.0;
  for (const Case& c :
       {Case{"m/s", Dim::kVelocity, 1.0}, Case{"cm/s", Dim::kVelocity, 1e-2},
        Case{"mm/s", Dim::kVelocity, 1e-3}, Case{"rad/s", Dim::kAngularVelocity, 1},
        Case{"deg/s", Dim::kAngularVelocity, deg},
        Case{"rpm", Dim::kAngularVelocity, 2 * std::numbers::pi / 60}, Case{"m", Dim::kLength, 1.0},
        Case{"cm", Dim::kLength, 1e-2}, Case{"mm", Dim::kLength, 1e-3}, Case{"s", Dim::kTime, 1.0},
        Case{"ms", Dim::kTime, 1e-3}, Case{"rad", Dim::kAngle, 1.0}, Case{"deg", Dim::kAngle, deg},
        Case{"-", Dim::kDimensionless, 1.0}}) {
    const units::Unit* u = units::find_unit(c.name);
    ASSERT_NE(u, nullptr) << c.name;
    EXPECT_EQ(u->dim, c.dim) << c.name;
    EXPECT_DOUBLE_EQ(u->to_si, c.to_si) << c.name;
    EXPECT_EQ(units::find_unit(c.name, c.dim), u) << c.name;
  }
}

TEST(Units, UnknownOrOfAnotherDimension) {
  EXPECT_EQ(units::find_unit("px"), nullptr);  // the track reader's own, not a physical unit
  EXPECT_EQ(units::find_unit("MM"), nullptr);  // case-sensitive
  EXPECT_EQ(units::find_unit(""), nullptr);
  EXPECT_EQ(units::find_unit("mm", Dim::kTime), nullptr);
  EXPECT_EQ(units::find_unit("deg", Dim::kAngularVelocity), nullptr);
}

TEST(Units, SiUnitsAndMessageLists) {
  EXPECT_STREQ(units::si_unit(Dim::kVelocity), "m/s");
  EXPECT_STREQ(units::si_unit(Dim::kAngularVelocity), "rad/s");
  EXPECT_STREQ(units::si_unit(Dim::kLength), "m");
  EXPECT_STREQ(units::si_unit(Dim::kTime), "s");
  EXPECT_STREQ(units::si_unit(Dim::kAngle), "rad");
  EXPECT_STREQ(units::si_unit(Dim::kDimensionless), "-");
  EXPECT_EQ(units::units_of(Dim::kLength), "m, cm, mm");
  EXPECT_EQ(units::units_of(Dim::kAngle), "rad, deg");
  EXPECT_EQ(units::units_of(Dim::kText),
            "m/s, cm/s, mm/s, rad/s, deg/s, rpm, m, cm, mm, s, ms, rad, deg, -");
  EXPECT_STREQ(units::dim_name(Dim::kAngularVelocity), "angular velocity");
  // Every unit's SI unit is in the table with factor 1.
  for (Dim d : {Dim::kVelocity, Dim::kAngularVelocity, Dim::kLength, Dim::kTime, Dim::kAngle,
                Dim::kDimensionless})
    EXPECT_EQ(units::find_unit(units::si_unit(d), d)->to_si, 1.0) << units::dim_name(d);
}

// The track reader reads its units from the same table: a track in cm and deg, the one unit
// the impact-set reader also knows, gives the SI values.
TEST(Units, TheTrackReaderUsesTheTable) {
  std::string text = "t[ms],x[cm],y[cm],theta[deg]\n";
  for (int i = 0; i < 6; ++i)
    text +=
        std::to_string(i) + "," + std::to_string(10 * i) + ",5," + std::to_string(30 * i) + "\n";
  const kinematics::Track tr = kinematics::parse_track_csv(text, "track.csv", std::nullopt, false);
  ASSERT_EQ(tr.t.size(), 6u);
  EXPECT_DOUBLE_EQ(tr.t[2], 2e-3);
  EXPECT_DOUBLE_EQ(tr.x[2], 0.2);
  EXPECT_DOUBLE_EQ(tr.y[0], 0.05);
  EXPECT_NEAR(tr.theta[1], std::numbers::pi / 6, 1e-12);
  try {
    kinematics::parse_track_csv("t[s],x[furlong],y[m],theta[rad]\n", "track.csv", std::nullopt,
                                false);
    FAIL() << "an unknown unit was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1u);
    EXPECT_EQ(e.field(), "x");
    EXPECT_EQ(e.detail(), "unknown unit 'furlong' (use px, m, cm, mm)");
  }
}

}  // namespace
}  // namespace ricochet
