// The diagnosis's sentences (diagnosis/evidence.hpp) say what its numbers mean and no more.
#include <gtest/gtest.h>

#include <string>

#include "diagnosis/diagnose.hpp"
#include "diagnosis/evidence.hpp"

namespace ricochet::diagnosis {
namespace {

// A confidence set that holds the law as it stands ("none") says only that no candidate beats
// it. Whether anything is missing is the floor's question: beside a "missing physics" verdict
// (the law's error above its floor) the sentence must not say that perhaps nothing is missing.
TEST(Evidence, AConfidenceSetHoldingNoneIsReadWithTheVerdict) {
  LawConfidenceSet cs;
  cs.models = 3;
  LawMember none;
  none.effect = "none";
  none.families = {Family::kNone};
  LawMember drag;
  drag.effect = "inertial_drag";
  drag.family = Family::kDrag;
  drag.families = {Family::kDrag};
  cs.members = {drag, none};
  ASSERT_TRUE(cs.holds_none());
  const std::string short_of_floor = detail::confidence_text(cs, true);
  EXPECT_EQ(short_of_floor.find("perhaps nothing is missing"), std::string::npos) << short_of_floor;
  EXPECT_NE(short_of_floor.find("not among the candidates"), std::string::npos) << short_of_floor;
  const std::string at_floor = detail::confidence_text(cs, false);
  EXPECT_NE(at_floor.find("perhaps nothing is missing"), std::string::npos) << at_floor;
  // Without "none" in the set neither reading is added.
  cs.members = {drag};
  EXPECT_EQ(detail::confidence_text(cs, true).find("the law as it stands"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::diagnosis
