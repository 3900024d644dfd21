// Runs the built `ricochet transfer` program: Table 3 from --json, the split (Fig. 12), seeded
// predictions, the model file round trip, the figures and the errors. RICOCHET_EXE is the
// program's path (set by CMake).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "impact/impact_set.hpp"
#include "support/program_test.hpp"
#include "table3.hpp"

namespace ricochet {
namespace {

using test::quote;
using test::slurp;
using Result = test::RunResult;

namespace fs = std::filesystem;
using nlohmann::json;
const std::string kLab = std::string(RICOCHET_SOURCE_DIR) + "/data/lab/";

class CmdTransfer : public test::ProgramTest {
 protected:
  json ricochet_json(const std::string& args) const {
    const Result r = ricochet(args + " --json");
    EXPECT_EQ(r.status, 0) << r.err;
    return json::parse(r.out);  // stdout holds exactly one JSON document
  }
};

void expect_row(const json& doc, const test::Table3Row& row) {
  EXPECT_EQ(doc["n"].get<std::size_t>(), row.n) << row.where;
  for (int c = 0; c < 3; ++c) {
    const char* k = kComponentNames[c];
    EXPECT_LE(std::abs(doc["A"][k].get<double>() - row.a[c]), 0.0005 + 1e-12)
        << row.file << " [" << row.where << "] A_" << k << " = " << doc["A"][k];
    EXPECT_LE(std::abs(doc["dA"][k].get<double>() - row.da[c]), 0.0005 + 1e-12)
        << row.file << " [" << row.where << "] dA_" << k << " = " << doc["dA"][k];
  }
}

TEST_F(CmdTransfer, Table3AllFourRowsFromJson) {
  for (const auto& row : test::kTable3) {
    std::string args = "transfer fit " + quote(kLab + row.file);
    if (row.where[0]) args += " --where " + quote(row.where);
    const json doc = ricochet_json(args);
    expect_row(doc, row);
    EXPECT_EQ(doc["command"], "transfer fit");
  }
}

TEST_F(CmdTransfer, SplitGivesTheTwoTriangleRowsAndFigure12) {
  const json doc = ricochet_json("transfer fit " + quote(kLab + "triangles.csv") +
                                 " --split vin_x=3.5 --figures " + quote(dir_.string()));
  expect_row(doc, test::kTable3[1]);
  expect_row(doc["split"]["below"], test::kTable3[2]);
  expect_row(doc["split"]["above"], test::kTable3[3]);
  EXPECT_EQ(doc["split"]["feature"], "vin_x");
  ASSERT_EQ(doc["figures"].size(), 2u);
  for (const auto& f : doc["figures"]) {
    // gnuplot names each series' group gnuplot_plot_<series><panel letter> (an opaque legend
    // repeats the groups, hence distinct ids).
    const std::string svg = slurp(f.get<std::string>());
    std::set<std::string> ids;
    const std::string tag = "<g id=\"gnuplot_plot_";
    for (auto p = svg.find(tag); p != std::string::npos; p = svg.find(tag, p + 1))
      ids.insert(svg.substr(p + tag.size(), svg.find('"', p + tag.size()) - p - tag.size()));
    const std::size_t groups = ids.size();
    // Three curves (incident, measured, predicted) per panel; 3 panels, or 2 x 3 for the split.
    EXPECT_EQ(groups, f.get<std::string>().find("split") != std::string::npos ? 18u : 9u) << f;
  }
}

TEST_F(CmdTransfer, FullMatrixLooAndKsAreReported) {
  const json doc = ricochet_json("transfer fit " + quote(kLab + "cylinders.csv"));
  ASSERT_TRUE(doc["full"].is_object());
  EXPECT_EQ(doc["full"]["M"].size(), 3u);
  EXPECT_EQ(doc["full"]["off_diagonal"].size(), 6u);
  for (const auto& o : doc["full"]["off_diagonal"]) EXPECT_GT(o["se"].get<double>(), 0);
  for (const char* model : {"constant", "diagonal", "diagonal_lsq", "full"})
    for (const char* k : {"vx", "vy", "w"})
      EXPECT_GT(doc["loo"]["rmse"][model][k].get<double>(), 0);
  for (const char* k : {"vx", "vy", "w"}) {
    const bool improves = doc["loo"]["full_improves"][k];
    EXPECT_EQ(improves, doc["loo"]["rmse"]["full"][k].get<double>() <
                            doc["loo"]["rmse"]["diagonal"][k].get<double>());
    const double p = doc["ks"][k]["p_value"];
    EXPECT_GE(p, 0);
    EXPECT_LE(p, 1);
  }
  EXPECT_EQ(doc["ks"]["n_predicted"].get<int>(), 28 * 100);
}

TEST_F(CmdTransfer, PredictIsReproducibleWithASeedAndDiffersWithAnother) {
  const std::string base =
      "transfer predict --vin 2.9,-2.3,-65 --from " + quote(kLab + "cylinders.csv") + " --n 200";
  const json a = ricochet_json(base + " --seed 11");
  const json b = ricochet_json(base + " --seed 11");
  const json c = ricochet_json(base + " --seed 12");
  ASSERT_EQ(a["samples"].size(), 200u);
  EXPECT_EQ(a["samples"], b["samples"]);
  EXPECT_NE(a["samples"], c["samples"]);
  // Every sample lies in [A - dA, A + dA] V_in for each component.
  const std::array<double, 3> vin{2.9, -2.3, -65};
  for (const auto& s : a["samples"])
    for (int k = 0; k < 3; ++k) {
      const double A = a["model"]["A"][kComponentNames[k]],
                   dA = a["model"]["dA"][kComponentNames[k]];
      const double ratio = s[k].get<double>() / vin[k];
      EXPECT_GE(ratio, A - dA - 1e-12);
      EXPECT_LE(ratio, A + dA + 1e-12);
    }
}

TEST_F(CmdTransfer, ModelFileFromFitDrivesPredict) {
  const std::string model = (dir_ / "fit.h5").string();
  const Result fit = ricochet("transfer fit " + quote(kLab + "triangles.csv") + " --where " +
                              quote("vin_x<3.5") + " --out " + quote(model));
  ASSERT_EQ(fit.status, 0) << fit.err;
  const std::string csv = (dir_ / "pred.csv").string();
  const json from_file = ricochet_json(
      "transfer predict --incident " + quote(kLab + "triangles.csv") + " --where " +
      quote("vin_x<3.5") + " --model " + quote(model) + " --seed 4 --n 3 --out " + quote(csv));
  const json from_data = ricochet_json(
      "transfer predict --incident " + quote(kLab + "triangles.csv") + " --where " +
      quote("vin_x<3.5") + " --from " + quote(kLab + "triangles.csv") + " --seed 4 --n 3");
  expect_row(from_file["model"],
             {"", "", 19, {0.757, -0.213, 0.452}, {0.218, 0.190, 0.155}, {}, {}});
  EXPECT_EQ(from_file["samples"], from_data["samples"]);
  EXPECT_EQ(from_file["n_samples"].get<int>(), 19 * 3);
  EXPECT_TRUE(from_file["ks"].is_object());
  // The CSV has a header and one row per sample.
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) continue;
    if (!header) {
      header = true;
      EXPECT_EQ(line.rfind("incident,replicate,vin_x[m/s]", 0), 0u) << line;
      continue;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 19 * 3);
}

TEST_F(CmdTransfer, ErrorsExitWithStatus2AndNameTheCulprit) {
  Result r = ricochet("transfer predict --vin 2.9,-2.3 --from " + quote(kLab + "cylinders.csv") +
                      " --seed 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--vin"), std::string::npos) << r.err;
  r = ricochet("transfer predict --vin 2.9,-2.3,-65 --model " + quote(kLab + "cylinders.csv") +
               " --seed 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cylinders.csv"), std::string::npos) << r.err;
  r = ricochet("transfer fit " + quote(kLab + "cylinders.csv") + " --where " + quote("vin_x>10"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--where"), std::string::npos) << r.err;
  r = ricochet("transfer fit " + quote(kLab + "cylinders.csv") + " --split vin_x");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--split"), std::string::npos) << r.err;
  r = ricochet("transfer predict --vin 2.9,-2.3,-65 --from " + quote(kLab + "cylinders.csv"));
  EXPECT_NE(r.status, 0);  // --seed is required
  EXPECT_NE(r.err.find("--seed"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ricochet
