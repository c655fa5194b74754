// Shared by the lab tests' validation files (triaxial_test, element_tests_test): a small
// dense sample of the triaxial kind and its element tests, and the CSV files they write.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "lab/triaxial_settings.hpp"

namespace geodem::test {

// A CSV file's header and rows; col(name) is the index of a column (a test failure if absent).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  }
};

inline Csv read_csv(const std::string& path) {
  Csv c;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string x; std::getline(hs, x, ',');) c.header.push_back(x);
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> r;
    for (std::string x; std::getline(ls, x, ',');) r.push_back(std::stod(x));
    c.rows.push_back(r);
  }
  return c;
}

// 400 discs (2D) or 300 spheres (3D) of contact friction 30 deg, prepared dense at 100 kPa
// between walls or in a periodic cell (whose packing, without the walls' looser
// neighbourhood, reaches a lower porosity); one test at 100 kPa, compressed to 2 %.
inline TriaxialSettings small_lab_sample(int dimension, bool periodic,
                                         LabKind kind = LabKind::kTriaxial) {
  TriaxialSettings s;
  s.kind = kind;
  s.periodic = periodic;
  s.dimension = dimension;
  s.box = std::vector<double>(static_cast<std::size_t>(dimension), 1.0);
  s.count = dimension == 2 ? 400 : 300;
  s.grain.young = 5e7;
  s.grain.friction = std::tan(30.0 * std::numbers::pi / 180.0);
  s.grain.density = 2600;
  s.wall = s.grain;
  s.wall.friction = 0.0;
  s.compaction_stress = 1e5;
  s.target_porosity = periodic ? (dimension == 2 ? 0.18 : 0.40) : (dimension == 2 ? 0.19 : 0.42);
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

}  // namespace geodem::test
