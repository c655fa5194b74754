// The element tests on small samples (docs/lab_tests.md): isotropic and oedometric steps
// end at rest on their stresses within 1 %; the oedometer's lateral strain stays zero (the
// axial strain equals the volumetric one to rounding) and K0 < 1 on loading; simple shear at
// constant volume keeps the volume to rounding and its shear strain is the imposed rate times
// the time (1e-9), the lateral strain staying zero; at constant normal stress the servo holds the
// normal stress within 1 %; cyclic loading gives G / Gmax falling and the damping ratio rising with
// the amplitude; the direct shear box's plate holds its normal stress within 1 %, no grain leaves
// the frames, and the shear stress rises from zero.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "base/text.hpp"
#include "lab/run_triaxial.hpp"
#include "test_util.hpp"
#include "validation/lab_test_util.hpp"

namespace geodem::test {
namespace {

TriaxialSettings small_sample(LabKind kind, int dimension, bool periodic) {
  return small_lab_sample(dimension, periodic, kind);
}

nlohmann::json run(const TriaxialSettings& s, const std::string& tag, Csv* history = nullptr) {
  RunOptions opt;
  opt.quiet = true;
  opt.out_dir = unique_temp_dir(tag);
  const auto summary = run_triaxial(s, opt);
  if (history) *history = read_csv(opt.out_dir + "/history.csv");
  return summary["results"];
}

struct StepCase {
  LabKind kind;
  int dimension;
  bool periodic;
};

// Isotropic and oedometric loading, unloading and reloading in steps of stress: each step
// ends at rest on its stress within 1 %; the void ratio falls on loading and rises on
// unloading; an oedometer keeps its lateral strain at zero, with K0 below 1 at the largest
// stress and rising on unloading.
void steps_end_on_their_stresses(const StepCase c) {
  TriaxialSettings s = small_sample(c.kind, c.dimension, c.periodic);
  s.element.stresses = {2e5, 4e5, 2e5};
  const std::string tag = cat(lab_kind_name(c.kind), c.dimension, c.periodic ? "p" : "w");
  Csv h;
  const auto r = run(s, tag, &h);
  ASSERT_EQ(r["points"].size(), 4u) << tag;
  double worst = 0.0;
  for (std::size_t i = 1; i < 4; ++i) {
    const auto& p = r["points"][i];
    const double target = s.element.stresses[i - 1];
    worst = std::max(worst, std::abs(p["sigma_axial"].get<double>() / target - 1.0));
    if (c.kind == LabKind::kIsotropic)
      worst = std::max(worst, std::abs(p["sigma_lateral"].get<double>() / target - 1.0));
  }
  report(tag + ": largest stress error at rest", worst);
  EXPECT_LT(worst, 0.01) << tag;
  // Loading compresses, unloading swells back part of it.
  const double e0 = r["points"][0]["void_ratio"], e1 = r["points"][2]["void_ratio"],
               e2 = r["points"][3]["void_ratio"];
  EXPECT_LT(e1, e0) << tag;
  EXPECT_GT(e2, e1) << tag;
  if (c.kind == LabKind::kOedometer) {
    double lateral = 0.0;
    for (const auto& row : h.rows)
      lateral =
          std::max(lateral, std::abs(row[h.col("axial_strain")] - row[h.col("volumetric_strain")]));
    report(tag + ": largest |axial - volumetric strain|", lateral);
    EXPECT_LT(lateral, 1e-12) << tag;
    EXPECT_LT(r["K0_at_largest_stress"].get<double>(), 1.0) << tag;
    EXPECT_GT(r["K0_end"].get<double>(), r["K0_at_largest_stress"].get<double>()) << tag;
  }
}

TEST(ElementTests, IsotropicAndOedometricStepsEndOnTheirStresses) {
  for (const StepCase c :
       {StepCase{LabKind::kIsotropic, 2, true}, StepCase{LabKind::kIsotropic, 2, false},
        StepCase{LabKind::kOedometer, 2, true}, StepCase{LabKind::kOedometer, 2, false}})
    steps_end_on_their_stresses(c);
}

// The periodic cell in 3D (its own test: the sanitizer run leaves it to the 2D cases).
TEST(ElementTests, OedometricStepsEndOnTheirStresses3D) {
  steps_end_on_their_stresses(StepCase{LabKind::kOedometer, 3, true});
}

TEST(ElementTests, SimpleShearAtConstantVolumeAndAtConstantNormalStress) {
  for (bool constant_volume : {true, false}) {
    TriaxialSettings s = small_sample(LabKind::kSimpleShear, 2, true);
    s.element.constant_volume = constant_volume;
    s.element.max_shear_strain = 0.05;
    s.element.shear_rate = 0.05;
    s.history_points = 100;
    const std::string tag =
        constant_volume ? "simple shear, constant volume" : "simple shear, constant normal stress";
    Csv h;
    const auto r = run(s, constant_volume ? "ss_cv" : "ss_cs", &h);
    const double t0 = h.rows.front()[h.col("time")] -
                      h.rows.front()[h.col("shear_strain")] / s.element.shear_rate;
    double volume = 0.0, rate = 0.0, normal = 0.0, lateral = 0.0;
    for (const auto& row : h.rows) {
      const double g = row[h.col("shear_strain")];
      rate = std::max(rate, std::abs(g - s.element.shear_rate * (row[h.col("time")] - t0)));
      volume = std::max(volume, std::abs(row[h.col("volumetric_strain")]));
      lateral = std::max(lateral,
                         std::abs(row[h.col("volumetric_strain")] - row[h.col("normal_strain")]));
      if (g > 0.005) normal = std::max(normal, std::abs(row[h.col("normal_stress")] / 1e5 - 1.0));
    }
    EXPECT_LT(lateral, 1e-12);  // the lateral axis is fixed: all volume change is normal
    if (constant_volume) {
      // dh_xn = L_xn h_nn dt with h_nn fixed: the tilt is L_xn t (a dilating cell's is not).
      report(tag + ": |shear strain - rate t|", rate);
      EXPECT_LT(rate, 1e-9);
      report(tag + ": largest |volumetric strain|", volume);
      EXPECT_LT(volume, 1e-12);
    } else {
      report(tag + ": largest normal stress error", normal);
      EXPECT_LT(normal, 0.01);
    }
    EXPECT_GT(r["tau_peak"].get<double>(), 0.0);
    EXPECT_GT(r["phi_mobilised_peak_deg"].get<double>(), 5.0);
  }
}

// One 400-disc sample is an anecdote: at 1e-4 one seed's G/Gmax is 0.96, the others' 1.00.
// The curves fall and rise on every seed; the levels are asserted on the mean of 5 seeds.
TEST(ElementTests, CyclicModulusFallsAndDampingRisesWithTheAmplitude) {
  const std::vector<double> amplitudes{1e-5, 1e-4, 1e-3, 1e-2};
  const int seeds = 5;
  std::vector<double> g_mean(4, 0.0), d_mean(4, 0.0);
  for (int seed = 1; seed <= seeds; ++seed) {
    TriaxialSettings s = small_sample(LabKind::kCyclicTriaxial, 2, true);
    s.seed = static_cast<std::uint64_t>(seed);
    s.element.amplitudes = amplitudes;
    s.element.cycles = 2;
    const auto r = run(s, cat("cyclic", seed));
    const auto& a = r["amplitudes"];
    ASSERT_EQ(a.size(), 4u);
    std::vector<double> g, d;
    for (const auto& x : a) g.push_back(x["G_over_Gmax"]), d.push_back(x["damping_ratio"]);
    for (std::size_t i = 0; i < 4; ++i) {
      g_mean[i] += g[i] / seeds;
      d_mean[i] += d[i] / seeds;
    }
    EXPECT_LT(g[2], g[1]) << "seed " << seed;
    EXPECT_LT(g[3], g[2]) << "seed " << seed;
    EXPECT_LT(std::abs(d[0]), 0.01) << "seed " << seed;
    EXPECT_GT(d[2], d[1]) << "seed " << seed;
    EXPECT_GT(d[3], d[2]) << "seed " << seed;
  }
  for (std::size_t i = 0; i < 4; ++i)
    report(cat("cyclic, 5 seeds: amplitude ", amplitudes[i], " mean G/Gmax"), g_mean[i]),
        report(cat("cyclic, 5 seeds: amplitude ", amplitudes[i], " mean damping"), d_mean[i]);
  EXPECT_NEAR(g_mean[1], 1.0, 0.02);  // still elastic at 1e-4
  EXPECT_LT(g_mean[2], 0.95);
}

// Stress control: each loop reaches its amplitude of q (within the 1 % the turn waits for),
// the modulus falls with it; an amplitude the sample cannot carry ends the test at the
// failure strain with a warning and the amplitudes before it measured.
TEST(ElementTests, StressControlledCyclesReachTheirAmplitudesOrStopAtFailure) {
  TriaxialSettings s = small_sample(LabKind::kCyclicTriaxial, 2, true);
  s.element.stress_cycles = true;
  s.element.amplitudes = {1e3, 1e4, 3e4, 9e4};
  s.element.cycles = 2;
  const auto r = run(s, "cyclic_stress");
  const auto& a = r["amplitudes"];
  ASSERT_EQ(a.size(), 3u);  // 90 kPa of q in extension exceeds the strength at 100 kPa
  double worst = 0.0;
  for (const auto& x : a) {
    const double q =
        2.0 * x["shear_modulus"].get<double>() * x["shear_strain_amplitude"].get<double>();
    worst = std::max(worst, std::abs(q / x["q_amplitude"].get<double>() - 1.0));
  }
  report("cyclic, stress control: largest |q range / 2 / amplitude - 1|", worst);
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(a[2]["G_over_Gmax"].get<double>(), a[1]["G_over_Gmax"].get<double>());
  EXPECT_GT(a[2]["damping_ratio"].get<double>(), a[1]["damping_ratio"].get<double>());
  ASSERT_TRUE(r.contains("warning"));
  EXPECT_NE(r["warning"].get<std::string>().find("failed"), std::string::npos);
}

// The shear box in 2D (segment frames) and 3D (rectangle frames): the plate holds its normal
// stress within 1 % while the upper frame slides, no grain leaves the box, and the stress
// ratio rises from rest to a peak.
void shear_box_holds_its_normal_stress_and_its_grains(const int dimension) {
  TriaxialSettings s = small_sample(LabKind::kDirectShear, dimension, false);
  s.box = dimension == 2 ? std::vector<double>{1.0, 0.5} : std::vector<double>{1.0, 0.6, 0.5};
  s.count = dimension == 2 ? 300 : 400;
  s.confining_stresses = {5e4, 1e5};
  s.strain_rate = 0.02;
  s.element.shear_velocity = 0.01;
  s.element.max_displacement = 0.03;
  s.history_points = 60;
  Csv h;
  const std::string tag = cat("direct shear ", dimension, "D");
  const auto r = run(s, cat("direct_shear", dimension), &h);
  double normal = 0.0;
  for (const auto& row : h.rows)
    if (row[h.col("displacement")] > 0.005) {
      const double target = s.confining_stresses[static_cast<std::size_t>(row[h.col("test")])];
      normal = std::max(normal, std::abs(row[h.col("normal_stress")] / target - 1.0));
    }
  report(tag + ": largest plate stress error", normal);
  EXPECT_LT(normal, 0.01) << tag;
  ASSERT_EQ(r["tests"].size(), 2u);
  for (const auto& t : r["tests"]) {
    EXPECT_EQ(t["grains_outside_box"].get<int>(), 0) << tag;
    EXPECT_GT(t["stress_ratio_peak"].get<double>(), 0.2) << tag;
    report(tag + ": peak stress ratio", t["stress_ratio_peak"].get<double>());
  }
  EXPECT_LT(std::abs(h.rows.front()[h.col("stress_ratio")]), 0.2) << tag;  // from rest
  EXPECT_TRUE(r["shear_envelope"].contains("phi_deg")) << tag;
}

TEST(ElementTests, DirectShearBoxHoldsItsNormalStressAndItsGrains) {
  shear_box_holds_its_normal_stress_and_its_grains(2);
}

// (Its own test: the sanitizer run leaves the 3D box to the 2D one, which runs its code but
// for the frames' shape.)
TEST(ElementTests, DirectShearBoxHoldsItsNormalStressAndItsGrains3D) {
  shear_box_holds_its_normal_stress_and_its_grains(3);
}

}  // namespace
}  // namespace geodem::test
