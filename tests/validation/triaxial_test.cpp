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

namespace geodem::test {
namespace {

template <typename T>
class Triaxial : public ::testing::Test {};
TYPED_TEST_SUITE(Triaxial, Dims, DimNames);

std::vector<std::vector<double>> read_csv(const std::string& path,
                                          std::vector<std::string>& header) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) header.push_back(c);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> r;
    for (std::string c; std::getline(ls, c, ',');) r.push_back(std::stod(c));
    rows.push_back(r);
  }
  return rows;
}

template <int D>
TriaxialSettings small_test(bool periodic) {
  TriaxialSettings s;
  s.periodic = periodic;
  s.dimension = D;
  s.box = std::vector<double>(D, 1.0);
  s.count = D == 2 ? 400 : 300;
  s.grain.young = 5e7;
  s.grain.friction = std::tan(30.0 * std::numbers::pi / 180.0);
  s.grain.density = 2600;
  s.wall = s.grain;
  s.wall.friction = 0.0;
  s.compaction_stress = 1e5;
  // Without walls (whose neighbourhood is looser) the same compaction is denser.
  s.target_porosity = periodic ? (D == 2 ? 0.18 : 0.40) : (D == 2 ? 0.19 : 0.42);
  s.max_multiplier = 1.0 + 2e4 / s.grain.young;
  s.final_max_multiplier = 1.0 + 2e3 / s.grain.young;
  s.strain_rate = 0.02;
  s.max_axial_strain = 0.02;
  s.confining_stresses = {1e5};
  s.servo_gain = periodic ? 0.1 : 0.5;
  s.vtk = false;
  s.plots = false;
  return s;
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

  std::vector<std::string> header;
  const auto rows = read_csv(opt.out_dir + "/history.csv", header);
  const auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
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
    std::vector<std::string> header;
    const auto rows = read_csv(opt.out_dir + "/history.csv", header);
    const auto col = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) -
                                      header.begin());
    };
    ASSERT_LT(col("excess_pore_pressure"), header.size());
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
