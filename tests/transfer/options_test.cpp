// The sampling options of `transfer fit` are checked once, by FitSampling::problems(): the
// defaults have none, an out-of-range value is a problem naming its field, and analyse_fit
// refuses it at its entry.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "transfer/transfer_io.hpp"

namespace ricochet::transfer {
namespace {

TEST(FitSamplingProblems, DefaultsHaveNoProblem) {
  EXPECT_TRUE(FitSampling{}.problems().empty());
}

TEST(FitSamplingProblems, ZeroReplicatesIsAProblemNamingTheOption) {
  FitSampling s;
  s.replicates = 0;
  const OptionProblems p = s.problems();
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].option, "replicates");
  EXPECT_EQ(p[0].message, "value 0 is outside [1, 1e+07]");
  try {
    (void)analyse_fit(ImpactSet{}, "", s);
    ADD_FAILURE() << "analyse_fit accepted replicates = 0";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "replicates");
  }
}

}  // namespace
}  // namespace ricochet::transfer
