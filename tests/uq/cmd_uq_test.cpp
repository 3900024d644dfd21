// Runs the built `ricochet montecarlo` and `ricochet sobol` programs: JSON contracts,
// reproducibility from the seed, HDF5 records, figures and input errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "common/h5.hpp"
#include "support/program_test.hpp"

namespace ricochet {
namespace {

namespace fs = std::filesystem;
using test::quote;
using test::RunResult;
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

class CmdUq : public test::ProgramTest {};

TEST_F(CmdUq, MonteCarloJsonContractAndSeed) {
  const std::string h5 = (dir_ / "mc.h5").string();
  const std::string args = "montecarlo --shape cylinder --n 3000 --seed 4 --compare " +
                           quote(kLab + "cylinders.csv") + " --json";
  const RunResult a =
      ricochet(args + " --out " + quote(h5) + " --figures " + quote((dir_ / "fig").string()));
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_TRUE(a.err.empty()) << a.err;  // no progress bar when stderr is not a terminal
  const auto doc = nlohmann::json::parse(a.out);
  EXPECT_EQ(doc["runs"], 3000);
  ASSERT_TRUE(doc["seconds"].is_number());
  for (const char* c : {"vx", "vy", "w"}) {
    ASSERT_TRUE(doc["ks"][c].is_number()) << c;
    const double p = doc["p_value"][c].get<double>();
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
  }
  EXPECT_EQ(doc["inputs"]["en2"]["lo"], 0.05);
  EXPECT_EQ(doc["inputs"]["mu"]["hi"], 0.6);
  const RunResult b = ricochet(args);
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(nlohmann::json::parse(b.out)["ks"], doc["ks"]);  // same seed, same answer
  const RunResult c = ricochet("montecarlo --shape cylinder --n 3000 --seed 5 --compare " +
                               quote(kLab + "cylinders.csv") + " --json");
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(nlohmann::json::parse(c.out)["reflected"], doc["reflected"]);
  h5::File f(h5, h5::File::Mode::kRead);
  std::vector<std::size_t> dims;
  f.read_doubles("/montecarlo/runs", &dims);
  ASSERT_EQ(dims.size(), 2u);
  EXPECT_EQ(dims[0], 3000u);
  EXPECT_EQ(dims[1], 3u + 8u);
  EXPECT_TRUE(fs::exists(dir_ / "fig" / "montecarlo_cdf.svg"));
}

TEST_F(CmdUq, MonteCarloWithoutCompareHasNoKs) {
  const RunResult r =
      ricochet("montecarlo --shape cylinder --n 200 --vin 3,-2.5,-60 --range en2=0.1:0.2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_FALSE(doc.contains("ks"));
  EXPECT_EQ(doc["inputs"]["en2"]["hi"], 0.2);
  EXPECT_EQ(doc["settings"]["incident"]["fixed"][0], 3.0);
}

TEST_F(CmdUq, SobolJsonContract) {
  const std::string h5 = (dir_ / "sobol.h5").string();
  const RunResult r = ricochet("sobol --shape cylinder --n 256 --bootstrap 30 --json --out " +
                               quote(h5) + " --figures " + quote((dir_ / "fig").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  for (const char* out : {"vx", "vy", "w"}) {
    for (const char* p : {"en2", "mu", "muR"}) {
      EXPECT_TRUE(doc["first_order"][out][p].is_number()) << out << " " << p;
      EXPECT_TRUE(doc["total_order"][out][p].is_number()) << out << " " << p;
      EXPECT_EQ(doc["intervals"]["first_order"][out][p].size(), 2u);
      EXPECT_EQ(doc["intervals"]["total_order"][out][p].size(), 2u);
    }
    EXPECT_TRUE(doc["second_order"][out]["en2-mu"].is_number());
    EXPECT_EQ(doc["intervals"]["second_order"][out]["mu-muR"].size(), 2u);
  }
  EXPECT_GT(doc["first_order"]["vy"]["en2"].get<double>(), 0.8);
  h5::File f(h5, h5::File::Mode::kRead);
  std::vector<std::size_t> dims;
  f.read_doubles("/sobol/first", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{3, 3}));
  f.read_doubles("/sobol/design_y", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{256 * 8, 3}));
  EXPECT_TRUE(fs::exists(dir_ / "fig" / "sobol.svg"));
}

TEST_F(CmdUq, BadInputsExitWithTwoAndNameTheOption) {
  RunResult r = ricochet("montecarlo --n 10 --range en2=0.3:0.1 --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--range"), std::string::npos) << r.err;
  r = ricochet("montecarlo --n 10 --range cd=0:1 --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cd"), std::string::npos) << r.err;
  r = ricochet("montecarlo --n 10 --vin 3,2,-60 --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--vin"), std::string::npos) << r.err;
  r = ricochet("sobol --n 64 --fix en2 --fix mu --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("two"), std::string::npos) << r.err;
  r = ricochet("sobol --n 64 --estimator bogus --json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--estimator"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ricochet
