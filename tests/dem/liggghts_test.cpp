// Real LIGGGHTS runs in this process on a small bed (about 2,000 grains): one impact end to end
// (decks, library interface, failure checks, reconstruction, HDF5) and the failure statuses.
// cli_test.cpp runs the `ricochet` program: 2 MPI ranks, a killed campaign that resumes.
//
// The bed is built once into RICOCHET_TEST_CACHE and reused by every test (the cache is keyed by
// the bed parameters and locked while a bed is built).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "bed.hpp"
#include "campaign.hpp"
#include "common/h5.hpp"
#include "dem_support.hpp"
#include "grain_calibration.hpp"
#include "impact/impact_set.hpp"
#include "impact_run.hpp"
#include "liggghts.hpp"
#include "synthetic_campaign.hpp"

namespace {

using namespace ricochet;
using namespace ricochet::dem;
namespace fs = std::filesystem;

using test::decks;
using test::kTestBed;

Overrides test_overrides(const std::vector<std::string>& extra = {}) {
  Overrides o;
  for (const auto& s : kTestBed) apply_set_option(decks(), s, o);
  for (const auto& s : extra) apply_set_option(decks(), s, o);
  return o;
}

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("dem-test-" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// The test bed (built once into the test cache).
BedFiles test_bed() {
  ImpactSpec spec;
  spec.params = test_overrides();
  return ensure_bed(decks(), bed_overrides(spec), RICOCHET_TEST_CACHE, MPI_COMM_WORLD);
}

ImpactResult run(ImpactSpec spec, const fs::path& work, ExtractOptions extract = {}) {
  ImpactContext ctx;
  ctx.decks = &decks();
  ctx.bed = ensure_bed(decks(), bed_overrides(spec), RICOCHET_TEST_CACHE, MPI_COMM_WORLD);
  ctx.template_include =
      ensure_template(Shape::resolve(spec.shape), ctx.bed, (work / "templates").string());
  ctx.work_dir = (work / spec.id).string();
  ctx.extract = extract;
  return run_impact(spec, ctx, MPI_COMM_WORLD);
}

TEST(DemEndToEnd, OneImpactThroughLiggghtsExtractionAndHdf5) {
  const fs::path work = temp_dir("e2e");
  ImpactSpec spec;
  spec.id = "e2e";
  spec.params = test_overrides();
  const ImpactResult r = run(spec, work);
  ASSERT_EQ(r.status, "rebound") << r.message;
  EXPECT_GT(r.grains, 1000);
  EXPECT_LT(r.grains, 4000);
  // The reconstruction (the lab's: ballistic fits at 400 frames/s around the contact window)
  // recovers the prescribed incident state and finds a rebound.
  const auto& rec = r.reconstruction;
  EXPECT_NEAR(rec.vin[kVx], 2.9, 0.05);
  EXPECT_NEAR(rec.vin[kVy], -2.3, 0.1);
  EXPECT_NEAR(rec.vin[kW], -65.0, 1.0);
  EXPECT_GE(rec.points_before, 3u);
  EXPECT_GE(rec.points_after, 3u);
  EXPECT_GT(rec.vout[kVy], 0.0);
  EXPECT_LT(rec.vout[kVy], 2.3);  // no energy created
  EXPECT_GT(rec.vout[kVx], 0.0);
  EXPECT_LT(rec.vout[kVx], 4.5);
  EXPECT_LT(rec.vout[kW], 0.0);
  EXPECT_GT(rec.vout[kW], -65.0);
  // The reconstructed V_out agrees with the block's own velocity after the contact.
  EXPECT_NEAR(rec.vout[kVx], r.v_end_direct[kVx], 0.25);
  EXPECT_NEAR(rec.vout[kVy], r.v_end_direct[kVy], 0.25);
  EXPECT_GT(r.penetration_max_m, 0.0);
  EXPECT_LT(r.penetration_max_m, 0.08);
  EXPECT_GT(r.energy_dissipated_frac, 0.0);
  EXPECT_LT(r.energy_dissipated_frac, 1.0);
  // The energy lost, two ways: LIGGGHTS's own kinetic energies of the multisphere over the force
  // window (ke/multisphere + erotate/multisphere, plus m g y), and the block's velocities at the
  // same instants with the lab cylinder's inertia (paper Fig. 4: I / m = R^2 / 2). They agree
  // to the clump's inertia error (on the rotational half of the energy) and the
  // potential energy over the window (a few mm of height: below 0.5 % of KE here).
  const Shape lab = Shape::cylinder();
  const double i_over_m = lab.inertia_kgm2 / lab.mass_kg;
  const auto ke = [&](const Vel3& v) {
    return v[kVx] * v[kVx] + v[kVy] * v[kVy] + i_over_m * v[kW] * v[kW];
  };
  ASSERT_GT(ke(r.v_start_direct), 0.0);
  // (Measured: 0.2162 against 0.2172 on this bed.)
  EXPECT_NEAR(1.0 - ke(r.v_end_direct) / ke(r.v_start_direct), r.energy_dissipated_frac, 0.01);
  EXPECT_GE(r.crater_depth_m, 0.0);
  EXPECT_LT(r.rayleigh_fraction, 0.2);

  // HDF5: the impact-set schema in /impacts, the track in /dem/tracks.
  const std::string h5 = (work / "out.h5").string();
  append_result(h5, r, spec, "test");
  const ImpactSet set = read_impact_set_h5(h5);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_EQ(set.impacts[0].id, "e2e");
  EXPECT_EQ(set.impacts[0].shape, "cylinder");
  EXPECT_DOUBLE_EQ(set.impacts[0].vout[kVy], rec.vout[kVy]);
  EXPECT_DOUBLE_EQ(*set.impacts[0].penetration, r.penetration_max_m);
  h5::File f(h5, h5::File::Mode::kRead);
  std::vector<std::size_t> dims;
  const auto track = f.read_doubles("/dem/tracks/e2e", &dims);
  ASSERT_EQ(dims.size(), 2u);
  EXPECT_EQ(dims[1], BlockTrack::column_names().size());
  EXPECT_EQ(dims[0], r.track.size());
  // The contact torque and the grains' largest overlap are recorded at every record, and the
  // records are at most record_dt_s (0.2 ms) apart.
  const BlockTrack back = read_campaign_track(h5, "e2e");
  ASSERT_EQ(back.size(), r.track.size());
  double torque_max = 0, overlap_max = 0;
  for (std::size_t i = 0; i < back.size(); ++i) {
    ASSERT_TRUE(std::isfinite(back.torque[i])) << i;
    ASSERT_TRUE(std::isfinite(back.overlap_d_max[i])) << i;
    torque_max = std::max(torque_max, std::abs(back.torque[i]));
    overlap_max = std::max(overlap_max, back.overlap_d_max[i]);
    if (i > 0) {
      EXPECT_LE(back.t[i] - back.t[i - 1], 2e-4 * (1 + 1e-9)) << i;
    }
  }
  EXPECT_GT(torque_max, 0.0);
  EXPECT_GT(overlap_max, 0.0);
  // The slab's block mass goes with its force: on the track and in the index.
  EXPECT_GT(r.block_mass_kg, 0.0);
  EXPECT_DOUBLE_EQ(back.block_mass_kg, r.block_mass_kg);
  EXPECT_LT(overlap_max, 0.3);  // (measured: 0.14 of d under the block on this bed)
  // Before the first contact (free flight) the torque is zero: gravity acts at the centre of mass.
  EXPECT_EQ(back.torque[0], 0.0);
  const auto index = read_campaign_index(h5);
  ASSERT_EQ(index.size(), 1u);
  EXPECT_EQ(index[0].status, "rebound");
  // Every column of the index row is where its name says.
  const auto& names = campaign_value_names();
  ASSERT_EQ(index[0].values.size(), names.size());
  auto col = [&](const std::string& n) {
    return index[0]
        .values[static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin())];
  };
  EXPECT_EQ(col("vout_y"), rec.vout[kVy]);
  EXPECT_EQ(col("steps"), static_cast<double>(r.steps));
  EXPECT_EQ(col("grains"), static_cast<double>(r.grains));
  EXPECT_EQ(col("cpu_s"), r.cpu_s);
  EXPECT_EQ(col("energy_dissipated_J"), r.energy_dissipated_J);
  EXPECT_EQ(col("penetration_max_m"), r.penetration_max_m);  // the last column
  EXPECT_GT(r.steps, 1000);
  EXPECT_LT(r.steps, 20000);  // the impact's own steps, not the bed's
  EXPECT_GT(r.cpu_s, 0.0);
}

// The packing measured on the restart against LIGGGHTS's own bookkeeping: the grains' mass, which
// it computed from each grain's density and radius at insertion (mass(all) / rho_grain is the
// volume by another path than measure_packing's sum of (4/3) pi r^3).
TEST(BedPacking, SolidFractionAgreesWithLiggghtsMassAndIsAPacking) {
  const BedFiles bed = test_bed();
  const BedPacking p = measure_packing(bed, MPI_COMM_WORLD);
  EXPECT_EQ(p.grains, bed.grains);
  const double rho = std::stod(bed.values.at("rho_grain"));
  const fs::path work = temp_dir("packing");
  double mass_kg = 0;
  {
    Liggghts lmp(MPI_COMM_WORLD, (work / "log").string(), (work / "screen").string(), {});
    lmp.read_bed_restart(bed.prefix + ".restart");
    lmp.command("variable m equal mass(all)");
    mass_kg = lmp.number("m").value();
  }
  EXPECT_NEAR(p.grain_volume_m3, mass_kg / rho, 1e-9 * p.grain_volume_m3);
  EXPECT_NEAR(p.solid_fraction, mass_kg / rho / (bed.Lx_m * bed.Ly_m * bed.z_surface_m), 1e-9);
  EXPECT_DOUBLE_EQ(p.bulk_density_kg_m3, p.solid_fraction * rho);
  // Poured polydisperse spheres settle between random loose (about 0.55) and random close
  // packing (about 0.64; Scott and Kilgour 1969); a wrong radius power or a wrong bed volume
  // lands far outside.
  EXPECT_GT(p.solid_fraction, 0.50);
  EXPECT_LT(p.solid_fraction, 0.66);
}

// The beds shipped for a campaign still running (scripts/ship-beds.sh, data/resolved/beds/FILE/):
// a new machine's campaign takes each one as built (scripts/stiffness-plateau.sh decompresses it
// into the cache), so each must be a whole restart that LIGGGHTS reads, of the grains its
// parameters file counts, settled into a packing. A truncated or mismatched copy would only show
// hours later, when the impact on it fails.
TEST(ShippedBeds, EachIsARestartOfTheGrainsItsParametersCount) {
  const fs::path root = fs::path(RICOCHET_SOURCE_DIR) / "data" / "resolved" / "beds";
  std::vector<fs::path> params;
  if (fs::exists(root))
    for (const auto& e : fs::recursive_directory_iterator(root))
      if (e.path().extension() == ".params") params.push_back(e.path());
  if (params.empty()) GTEST_SKIP() << "no bed shipped under " << root;
  const fs::path work = temp_dir("shipped-beds");
  for (const fs::path& p : params) {
    SCOPED_TRACE(p.string());
    const fs::path xz = p.parent_path() / (p.stem().string() + ".restart.xz");
    ASSERT_TRUE(fs::exists(xz)) << "the parameters file has no restart beside it";
    const fs::path prefix = work / p.stem();
    // xz checks the stream's CRC64 as it decompresses: a damaged copy exits non-zero.
    ASSERT_EQ(
        std::system(("xz -dc '" + xz.string() + "' > '" + prefix.string() + ".restart'").c_str()),
        0);
    fs::copy_file(p, prefix.string() + ".params");
    const BedFiles bed = read_bed_files(prefix.string());
    EXPECT_TRUE(bed.settled);
    const BedPacking packing = measure_packing(bed, MPI_COMM_WORLD);
    EXPECT_EQ(packing.grains, bed.grains);
    EXPECT_GT(packing.solid_fraction, 0.50);  // the bounds of the test above
    EXPECT_LT(packing.solid_fraction, 0.66);
    fs::remove(prefix.string() + ".restart");
  }
}

// A shipped bed is found on a new machine only under its key, which hashes the bed decks' text
// (params.hpp, bed_key): so each beds folder ships the decks its campaign pinned
// (pinned-decks.tar.xz, scripts/pack-decks.py), which the new machine pins (scripts/
// pin-program.sh). Each shipped bed's key must be the one those decks give its parameters; the
// tree's decks gave another key for the speed campaign's bed on 2026-12-07, and the bed went
// unfound. A folder with anything shipped (a bed, a build's or an impact's checkpoint) carries the
// decks and names its results folder.
TEST(ShippedBeds, EachFolderCarriesTheDecksThatKeyItsBeds) {
  const fs::path root = fs::path(RICOCHET_SOURCE_DIR) / "data" / "resolved" / "beds";
  if (!fs::exists(root)) GTEST_SKIP() << "nothing shipped under " << root;
  const fs::path work = temp_dir("shipped-decks");
  int folders = 0, beds = 0;
  for (const auto& dir : fs::directory_iterator(root)) {
    if (!dir.is_directory()) continue;
    SCOPED_TRACE(dir.path().string());
    ++folders;
    std::ifstream pinned_in(dir.path() / "pinned-in");
    std::string folder;
    EXPECT_TRUE(std::getline(pinned_in, folder) && !folder.empty()) << "no pinned-in";
    const fs::path tarball = dir.path() / "pinned-decks.tar.xz";
    ASSERT_TRUE(fs::exists(tarball)) << "no pinned decks";
    const fs::path into = work / dir.path().filename();
    fs::create_directories(into);
    ASSERT_EQ(
        std::system(("tar -xJf '" + tarball.string() + "' -C '" + into.string() + "'").c_str()), 0);
    const Decks shipped = Decks::locate((into / "liggghts-inputs").string());
    for (const auto& e : fs::directory_iterator(dir.path())) {
      if (e.path().extension() != ".params") continue;
      ++beds;
      // The bed's parameters as its build wrote them (read_bed_files): bed_key takes the decks'
      // bed parameters from them, in canonical form.
      const fs::path prefix = e.path().parent_path() / e.path().stem();
      const std::string key = e.path().stem().string().substr(4);  // bed-KEY.params
      EXPECT_EQ(bed_key(shipped, read_bed_files(prefix.string()).values), key) << e.path();
    }
  }
  RecordProperty("folders", folders);
  RecordProperty("beds", beds);
}

// calibrate-grains's bulk constraint on a synthetic campaign (synthetic_campaign.hpp) whose design
// points sit on beds of known solid fraction: each point's bed is the test bed's restart under its
// own key, with a levelled surface set so that phi = 0.50 + 0.30 (mu_gg - 0.5), a packing that
// densifies with friction as no poured sand does, on purpose: the target (mu_gg = 0.78, phi 0.584)
// then lies outside the band [0.52, 0.56], and the search must give up some V_out^x to stay in it.
TEST(BedPacking, CalibrateGrainsMeasuresEachPointsBedAndKeepsTheOptimumInTheBand) {
  const BedFiles bed = test_bed();
  const double phi0 = measure_packing(bed, MPI_COMM_WORLD).solid_fraction;
  const fs::path dir = temp_dir("packing-band");
  const fs::path cache = dir / "cache";
  fs::create_directories(cache);
  auto phi_of = [](double mu) { return 0.50 + 0.30 * (mu - 0.5); };
  // Each rank (a process of its own) writes its own campaign and cache in its own folder and
  // calibrates alone: calibrate_grains measures the beds on MPI_COMM_SELF.
  const std::string path = test::make_campaign(dir, 24, [&](double mu, double, double) {
    const std::string key = fmt::format("synth{:.4f}", mu);
    const fs::path prefix = cache / ("bed-" + key);
    if (fs::exists(prefix.string() + ".params")) return key;
    fs::copy_file(bed.prefix + ".restart", prefix.string() + ".restart");
    std::ifstream in(bed.prefix + ".params");
    std::ofstream out(prefix.string() + ".params");
    for (std::string line; std::getline(in, line);)
      out << (line.rfind("variable z_surface_m ", 0) == 0
                  ? fmt::format("variable z_surface_m string {:.17g}",
                                bed.z_surface_m * phi0 / phi_of(mu))
                  : line)
          << "\n";
    return key;
  });
  GrainCalibrationOptions o;
  o.sobol_n = 2000;
  o.search_n = 8000;
  o.bed_cache = cache.string();
  const auto free = calibrate_grains(path, decks(), test::target_set(), o);
  o.solid_fraction = {0.52, 0.56};
  const auto banded = calibrate_grains(path, decks(), test::target_set(), o);
  ASSERT_EQ(banded.parameters[1], "bed.mu_gg");
  for (const auto& p : banded.points) EXPECT_NEAR(p.solid_fraction, phi_of(p.x[1]), 2e-4);
  EXPECT_GT(banded.solid_fraction_q2, 0.99);
  // Unconstrained, the calibrated point is the target's, outside the band.
  EXPECT_NEAR(free.best[1], 0.78, 0.05);
  EXPECT_GT(free.best_solid_fraction, 0.57);
  // Constrained: inside the band, at its dense edge (the closest to the target's friction).
  EXPECT_GE(banded.best_solid_fraction, 0.52);
  EXPECT_LE(banded.best_solid_fraction, 0.56);
  EXPECT_NEAR(banded.best_solid_fraction, 0.56, 0.01);
  EXPECT_NEAR(banded.best[1], 0.70, 0.04);
  // The band holds mu_gg in [0.567, 0.70]: 27 % of the sampled range [0.5, 1.0].
  EXPECT_NEAR(banded.admissible_fraction, 0.133 / 0.5, 0.03);
  EXPECT_GT(banded.best_misfit, free.best_misfit);
}

TEST(DemFailures, InsertionOutsideTheBedIsRefusedBeforeLiggghts) {
  const fs::path work = temp_dir("outside");
  ImpactSpec spec;
  spec.id = "outside";
  spec.params = test_overrides({"run.x_impact_frac=0.05"});
  const ImpactResult r = run(spec, work);
  EXPECT_EQ(r.status, "invalid");
  EXPECT_NE(r.message.find("from the wall behind it"), std::string::npos) << r.message;
  EXPECT_EQ(r.steps, 0);  // LIGGGHTS was never started
  EXPECT_FALSE(fs::exists(work / "outside" / "log.liggghts"));
}

TEST(DemFailures, TimeStepTooLargeIsDetected) {
  const fs::path work = temp_dir("dt");
  ImpactSpec spec;
  spec.id = "dt";
  spec.params = test_overrides({"run.dt_scale=3"});
  const ImpactResult r = run(spec, work);
  EXPECT_EQ(r.status, "timestep") << r.message;
  EXPECT_GT(r.rayleigh_fraction, 0.2);
  EXPECT_NE(r.message.find("Rayleigh"), std::string::npos);
  EXPECT_FALSE(r.ok());
}

TEST(DemFailures, NoEndOfReboundWithinTheTimeLimitIsATimeout) {
  const fs::path work = temp_dir("timeout");
  ImpactSpec spec;
  spec.id = "timeout";
  spec.params = test_overrides({"run.t_max_s=0.02"});
  const ImpactResult r = run(spec, work);
  EXPECT_EQ(r.status, "timeout") << r.message;
  EXPECT_GE(r.sim_time_s, 0.02);
  EXPECT_LT(r.sim_time_s, 0.025);
  // A failed impact is recorded with its status and no velocities.
  const std::string h5 = (work / "out.h5").string();
  append_result(h5, r, spec, "test");
  const auto index = read_campaign_index(h5);
  ASSERT_EQ(index.size(), 1u);
  EXPECT_EQ(index[0].status, "timeout");
  EXPECT_TRUE(std::isnan(index[0].values[3]));  // vout_x
  h5::File f(h5, h5::File::Mode::kRead);
  EXPECT_FALSE(f.exists("/impacts"));
}

// Two LIGGGHTS instances run one after the other in one process give the same impact bit for bit,
// as a campaign's rank runs its impacts. Until impact/setup.in set the grains' body ids, fix
// multisphere left them uninitialised: the first instance of a process read zeros and dropped
// every grain pair from its first neighbour list, the next ones read the previous instance's
// leftovers (on this bed V_out^y was 0.7368, then 0.7290 m/s).
TEST(DemReproducibility, TheSameImpactTwiceInOneProcessIsBitForBitTheSame) {
  const fs::path work = temp_dir("twice");
  ImpactSpec first;
  first.id = "first";
  first.params = test_overrides();
  ImpactSpec again = first;
  again.id = "again";
  const ImpactResult a = run(first, work), b = run(again, work);
  ASSERT_EQ(a.status, "rebound") << a.message;
  ASSERT_EQ(b.status, "rebound") << b.message;
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a.reconstruction.vout[k], b.reconstruction.vout[k]) << k;
  ASSERT_EQ(a.track.size(), b.track.size());
  for (std::size_t i = 0; i < a.track.size(); ++i)
    ASSERT_EQ(a.track.ke_grains[i], b.track.ke_grains[i]) << i;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  MPI_Finalize();
  return rc;
}
