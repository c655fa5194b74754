// Material files: what the calibration writes is what a scenario reads back, the
// scenario's own keys win, and bad references or values name the right file.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/material_file.hpp"
#include "lab/triaxial_settings.hpp"

namespace geodem {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("geodem_material_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

const char* kScenario = R"(kind = "triaxial"
dimension = 2
[sample]
box = [1.0, 2.0]
count = 100
[material]
file = "soil.toml"
kt_over_kn = 0.4
[compaction]
confining_stress = 1e4
[shear]
confining_stress = [1e4]
)";

MaterialFile example() {
  MaterialFile m;
  m.name = "test soil";
  m.dimension = 2;
  m.material = {{"density", 2300.0},      {"young", 3.5e7},         {"kt_over_kn", 0.25},
                {"friction_deg", 33.5},   {"normal_cohesion", 8e4}, {"shear_cohesion", 8e4},
                {"rolling_friction", 0.1}};
  m.grain = "pair_0.9";
  m.radius_fuzz = 0.2;
  m.porosity = 0.21;
  m.macro = {{"phi_peak_deg", 34.0}};
  return m;
}

TEST(MaterialFile, RoundTripIntoAScenarioWithOverrides) {
  const fs::path d = temp_dir();
  write_material_file((d / "soil.toml").string(), example());
  const std::string scenario = (d / "scenario.toml").string();
  toml::table root = toml::parse(kScenario, scenario);
  expand_material_reference(root, "triaxial", scenario);
  const TriaxialSettings s = read_triaxial(root, scenario);
  EXPECT_EQ(s.grain.density, 2300.0);
  EXPECT_EQ(s.grain.young, 3.5e7);
  EXPECT_EQ(s.grain.kt_over_kn, 0.4);  // the scenario's own value
  EXPECT_NEAR(std::atan(s.grain.friction) * 180.0 / 3.14159265358979323846, 33.5, 1e-12);
  EXPECT_EQ(s.grain.normal_cohesion, 8e4);
  EXPECT_EQ(s.grain.rolling_friction, 0.1);
  ASSERT_EQ(s.grains.kinds.size(), 1u);
  EXPECT_EQ(s.grains.kinds[0].shape, "pair_0.9");
  EXPECT_EQ(s.radius_fuzz, 0.2);
  EXPECT_EQ(s.target_porosity, 0.21);
  EXPECT_EQ(s.bonds_create, "after_compaction");  // cohesive material: bonds by default
  fs::remove_all(d);
}

TEST(MaterialFile, BadReferencesAndValuesNameTheFile) {
  const fs::path d = temp_dir();
  const std::string scenario = (d / "scenario.toml").string();
  {  // missing file
    toml::table root = toml::parse(kScenario, scenario);
    try {
      expand_material_reference(root, "triaxial", scenario);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("material.file"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos) << e.what();
    }
  }
  {  // wrong dimension
    MaterialFile m = example();
    m.dimension = 3;
    write_material_file((d / "soil.toml").string(), m);
    toml::table root = toml::parse(kScenario, scenario);
    EXPECT_THROW(expand_material_reference(root, "triaxial", scenario), InputError);
  }
  {  // a bad value in the material file is reported against the material file
    MaterialFile m = example();
    m.material["young"] = -1.0;
    write_material_file((d / "soil.toml").string(), m);
    toml::table root = toml::parse(kScenario, scenario);
    try {
      expand_material_reference(root, "triaxial", scenario);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find((d / "soil.toml").string()), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("material.young"), std::string::npos) << e.what();
    }
  }
  {  // unknown preset: the shipped ones are listed
    toml::table root = toml::parse(
        "kind = \"triaxial\"\ndimension = 2\n[material]\npreset = \"no_such_soil\"\n", scenario);
    try {
      expand_material_reference(root, "triaxial", scenario);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("unknown preset"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(d);
}

}  // namespace
}  // namespace geodem
