// --where filters on impact sets.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/error.hpp"
#include "impact/impact_set.hpp"
#include "impact/release_index.hpp"

namespace ricochet {
namespace {

const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

ImpactSet lab() {
  ImpactSet set = read_impact_set(kLab + "cylinders.csv");
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  set.impacts.insert(set.impacts.end(), tri.impacts.begin(), tri.impacts.end());
  return set;
}

// Counts by brute force what a numeric condition should keep.
template <typename Pred>
std::size_t count_if_impacts(const ImpactSet& set, Pred pred) {
  std::size_t n = 0;
  for (const auto& m : set.impacts) n += pred(m) ? 1 : 0;
  return n;
}

TEST(ImpactFilter, PaperSplitOfTriangles) {
  const ImpactSet tri = read_impact_set(kLab + "triangles.csv");
  // Paper Table 3 splits the 31 triangles at V_in^x = 3.5 m/s into 19 and 12 releases.
  EXPECT_EQ(filter(tri, "vin_x<3.5").size(), 19u);
  EXPECT_EQ(filter(tri, "vin_x>3.5").size(), 12u);
  EXPECT_EQ(filter(tri, " vin_x >= 3.5 ").size(), 12u);
}

TEST(ImpactFilter, EveryOperatorAgreesWithBruteForce) {
  const ImpactSet set = lab();
  const double t = 3.05;
  EXPECT_EQ(filter(set, "vin_x<3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] < t; }));
  EXPECT_EQ(filter(set, "vin_x<=3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] <= t; }));
  EXPECT_EQ(filter(set, "vin_x>3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] > t; }));
  EXPECT_EQ(filter(set, "vin_x>=3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] >= t; }));
  EXPECT_EQ(filter(set, "vin_x==3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] == t; }));
  EXPECT_EQ(filter(set, "vin_x!=3.05").size(),
            count_if_impacts(set, [&](const Impact& m) { return m.vin[kVx] != t; }));
  // 3.05 occurs in the data, so <= and < differ.
  EXPECT_GT(filter(set, "vin_x==3.05").size(), 0u);
  EXPECT_EQ(filter(set, "speed_in>4").size(), count_if_impacts(set, [](const Impact& m) {
              return std::hypot(m.vin[kVx], m.vin[kVy]) > 4;
            }));
}

TEST(ImpactFilter, TextConditionsAndConjunctions) {
  const ImpactSet set = lab();
  EXPECT_EQ(filter(set, "shape==triangle").size(), 31u);
  EXPECT_EQ(filter(set, "shape=='cylinder'").size(), 28u);
  EXPECT_EQ(filter(set, "shape!=\"cylinder\"").size(), 31u);
  EXPECT_EQ(filter(set, "vin_x>=3.5 && shape==triangle").size(), 12u);
  EXPECT_EQ(filter(set, "vin_x>=3.5 and shape==triangle").size(), 12u);
  EXPECT_EQ(filter(set, "vin_x>=3.5 AND shape==triangle && wout<-19").size(),
            count_if_impacts(set, [](const Impact& m) {
              return m.vin[kVx] >= 3.5 && m.shape == "triangle" && m.vout[kW] < -19;
            }));
  const ImpactSet no_c12 = filter(set, "id!=C12");
  EXPECT_EQ(no_c12.size(), 58u);
  for (const auto& m : no_c12.impacts) EXPECT_NE(m.id, "C12");
  EXPECT_EQ(filter(set, "operator==2").size(), 59u);
  EXPECT_EQ(filter(set, "").size(), 59u);
}

// '^=' keeps the text fields that start with the value: a campaign's level or state by the prefix
// of its ids (E1.5e9-T18-s0, ...), which '==' and '!=' could only list one by one.
TEST(ImpactFilter, PrefixConditionsKeepTheIdsThatStartWithTheValue) {
  const ImpactSet set = lab();
  const ImpactSet t1 = filter(set, "id^=T1");
  EXPECT_EQ(t1.size(),
            count_if_impacts(set, [](const Impact& m) { return m.id.starts_with("T1"); }));
  EXPECT_EQ(t1.size(), 10u);  // T10-T19
  EXPECT_EQ(filter(set, "id^='T'").size(), 31u);
  EXPECT_EQ(filter(set, "shape^=tri && id^=T3").size(), 2u);  // T30, T31
  EXPECT_EQ(filter(set, "id^=T1 && id!=T10").size(), 9u);
  EXPECT_EQ(filter(set, "id^=X").size(), 0u);
}

TEST(ImpactFilter, KeepsProvenanceAndOrder) {
  const ImpactSet set = read_impact_set(kLab + "triangles.csv");
  const ImpactSet out = filter(set, "vin_x<3.5");
  EXPECT_EQ(out.comments.back(), "filter: vin_x<3.5");
  EXPECT_EQ(out.impacts.front().id, "T03");
  EXPECT_EQ(out.impacts.back().id, "T31");
}

TEST(ImpactFilter, MissingValuesMatchNothing) {
  const std::string text =
      "id,shape,vin_x[m/s],vin_y[m/s],win[rad/s],vout_x[m/s],vout_y[m/s],wout[rad/s],"
      "penetration[m],operator\n"
      "A,cylinder,1,-1,-10,1,0.5,-5,0.01,x\n"
      "B,cylinder,1,-1,-10,1,0.5,-5,,\n";
  const ImpactSet set = parse_impact_set_csv(text, "m.csv");
  EXPECT_EQ(filter(set, "penetration<1").size(), 1u);
  EXPECT_EQ(filter(set, "penetration!=5").size(), 1u);
  EXPECT_EQ(filter(set, "operator!=y").size(), 1u);
}

TEST(ImpactFilter, MalformedFiltersNameTheTerm) {
  const ImpactSet set = lab();
  auto field_of = [&](const std::string& where) -> std::string {
    try {
      filter(set, where);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "--where");
      return e.field();
    }
    ADD_FAILURE() << "accepted: " << where;
    return {};
  };
  EXPECT_EQ(field_of("vin_x 3.5"), "vin_x 3.5");            // no operator
  EXPECT_EQ(field_of("vin_x=3.5"), "vin_x=3.5");            // '=' alone
  EXPECT_EQ(field_of("vinx<3.5"), "vinx<3.5");              // unknown feature
  EXPECT_EQ(field_of("vin_x<fast"), "vin_x<fast");          // not a number
  EXPECT_EQ(field_of("vin_x<nan"), "vin_x<nan");            // not finite
  EXPECT_EQ(field_of("vin_x<<3"), "vin_x<<3");              // two operators
  EXPECT_EQ(field_of("shape<triangle"), "shape<triangle");  // text ordering
  EXPECT_EQ(field_of("vin_x<3 && "), "vin_x<3 && ");        // dangling &&
  EXPECT_EQ(field_of("shape==triangle && <3"), "<3");       // no feature
  EXPECT_EQ(field_of("vin_x<"), "vin_x<");                  // no value
  EXPECT_EQ(field_of("vin_x^=3"), "vin_x^=3");              // starts-with on a number
  EXPECT_EQ(field_of("id^^=T"), "id^^=T");                  // two operators
  try {
    filter(set, "vinx<3.5");
  } catch (const InputError& e) {
    EXPECT_NE(e.detail().find("vin_x"), std::string::npos) << "should list known features";
  }
}

// A campaign impact names the release it was run at by its id, or by the longest prefix of its id
// that ends before a '-'; a release whose own id has a '-' is found whole.
TEST(ReleaseIndex, MatchesAnImpactToTheReleaseItWasRunAt) {
  ImpactSet releases;
  for (const char* id : {"C02", "C02-b", "T1"}) {
    Impact im;
    im.id = id;
    releases.impacts.push_back(im);
  }
  const ReleaseIndex index(releases);
  EXPECT_EQ(index.find("C02"), 0u);
  EXPECT_EQ(index.find("C02-x_impact_frac0.26"), 0u);
  EXPECT_EQ(index.find("C02-b"), 1u);        // the release's own id, not its prefix
  EXPECT_EQ(index.find("C02-b-s1"), 1u);     // the longest prefix
  EXPECT_EQ(index.find("T1-s0-extra"), 2u);  // prefixes tried from the longest down
  EXPECT_FALSE(index.find("C0"));
  EXPECT_FALSE(index.find("C021"));
  EXPECT_FALSE(index.find("-C02"));
  EXPECT_FALSE(index.find(""));
}

}  // namespace
}  // namespace ricochet
