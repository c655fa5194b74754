// The lab test's controllers on small samples, discs and spheres, between walls and in a
// periodic cell: the prepared sample reaches the isotropic stress within 1 % and the target
// porosity within 0.005; during compression at the standard 0.02 /s the servo (of the walls,
// or of the cell) holds sigma3 within 1 % of its target (after the first 0.5 % of axial
// strain), and q starts from zero and rises.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "lab/run_triaxial.hpp"
#include "test_util.hpp"
#include "validation/lab_test_util.hpp"

namespace geodem::test {
namespace {

template <typename T>
class Triaxial : public ::testing::Test {};
TYPED_TEST_SUITE(Triaxial, Dims, DimNames);

template <int D>
TriaxialSettings small_test(bool periodic) {
  return small_lab_sample(D, periodic);
}

template <int D>
void check_preparation_and_servo(bool periodic) {
  const TriaxialSettings s = small_test<D>(periodic);
  RunOptions opt;
  opt.quiet = true;
  opt.out_dir = test::unique_temp_dir("triaxial" + std::to_string(D));
  const auto summary = run_triaxial(s, opt);
  const std::string tag = std::to_string(D) + (periodic ? "D periodic" : "D");
  const auto& prep = summary["results"]["preparation"];
  report(tag + " prepared porosity - target", prep["porosity"].get<double>() - s.target_porosity);
  report(tag + " prepared mean stress / target - 1",
         prep["mean_stress"].get<double>() / s.compaction_stress - 1.0);
  EXPECT_FALSE(prep.contains("warning"));
  EXPECT_NEAR(prep["porosity"].get<double>(), s.target_porosity, 0.005);
  EXPECT_NEAR(prep["mean_stress"].get<double>(), s.compaction_stress, 0.01 * s.compaction_stress);

  const Csv csv = read_csv(opt.out_dir + "/history.csv");
  const auto& rows = csv.rows;
  const auto col = [&](const std::string& name) { return csv.col(name); };
  ASSERT_GT(rows.size(), 50u);
  double worst = 0.0;
  for (const auto& r : rows)
    if (r[col("axial_strain")] > 0.005)
      worst = std::max(worst, std::abs(r[col("sigma3")] / 1e5 - 1.0));
  report(tag + " servo: largest |sigma3/target - 1| after 0.5 % strain", worst);
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(std::abs(rows.front()[col("q")]), 0.02 * 1e5);
  EXPECT_GT(rows.back()[col("q")], 0.3 * 1e5);
}

TYPED_TEST(Triaxial, PreparationAndServoHoldTheirTargets) {
  check_preparation_and_servo<TypeParam::value>(false);
}

TYPED_TEST(Triaxial, PeriodicCellPreparationAndServoHoldTheirTargets) {
  check_preparation_and_servo<TypeParam::value>(true);
}

// Undrained (constant-volume) compression, walls and periodic cell: the volume stays
// constant (the lateral rates cancel the axial one to first order in the step), and the
// excess pore pressure recorded is sigma3 + q/3 (2D: q/2) - p' on every row.
TYPED_TEST(Triaxial, UndrainedCompressionKeepsTheVolume) {
  constexpr int D = TypeParam::value;
  for (bool periodic : {false, true}) {
    TriaxialSettings s = small_test<D>(periodic);
    s.undrained = true;
    RunOptions opt;
    opt.quiet = true;
    opt.out_dir = test::unique_temp_dir("undrained" + std::to_string(D) + (periodic ? "p" : "w"));
    const auto summary = run_triaxial(s, opt);
    const Csv csv = read_csv(opt.out_dir + "/history.csv");
    const auto& rows = csv.rows;
    const auto col = [&](const std::string& name) { return csv.col(name); };
    ASSERT_LT(col("excess_pore_pressure"), csv.header.size());
    double worst_volume = 0.0, worst_u = 0.0;
    for (const auto& r : rows) {
      worst_volume = std::max(worst_volume, std::abs(r[col("volumetric_strain")]));
      const double u = 1e5 + r[col("q")] / (D == 3 ? 3.0 : 2.0) - r[col("p")];
      worst_u = std::max(worst_u, std::abs(r[col("excess_pore_pressure")] - u) / 1e5);
    }
    const std::string tag = std::to_string(D) + (periodic ? "D periodic" : "D walls");
    report(tag + " undrained: largest |volumetric strain| to 2 % axial", worst_volume);
    EXPECT_LT(worst_volume, 1e-6);
    EXPECT_LT(worst_u, 1e-12);
    EXPECT_GT(rows.back()[col("axial_strain")], 0.019);
    EXPECT_EQ(summary["results"]["drainage"], "undrained");
  }
}

}  // namespace
}  // namespace geodem::test
