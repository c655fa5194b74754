// Settings of the element tests that share the triaxial kind's sample and preparation
// (docs/element_tests.md): kind = "isotropic", "oedometer", "simple_shear",
// "cyclic_triaxial", "direct_shear".
// Their loading program is read from the [loading] table in place of [shear].
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace geodem {

class TableReader;

enum class LabKind : std::uint8_t {
  kTriaxial,        // drained or undrained compression (lab/run_triaxial.cpp)
  kIsotropic,       // isotropic loading and unloading by steps of mean stress
  kOedometer,       // axial loading and unloading by steps, lateral strain zero
  kSimpleShear,     // periodic cell sheared at constant normal stress or constant volume
  kCyclicTriaxial,  // strain-controlled cycles of axial strain at constant confining stress
  kDirectShear      // shear box: upper frame slid at constant speed under a normal stress
};

const char* lab_kind_name(LabKind k);

struct ElementTestSettings {
  // isotropic: mean stresses; oedometer: axial stresses (Pa). Applied in order, each held
  // until the sample is at rest: loading steps, then unloading steps.
  std::vector<double> stresses;
  // simple_shear
  bool constant_volume = false;  // control = "constant_volume"; else constant normal stress
  double shear_rate = 0.02;      // 1/s
  double max_shear_strain = 0.3;
  // cyclic_triaxial: single amplitudes of axial strain, in increasing order, on one sample
  std::vector<double> amplitudes;  // or of the deviator q (Pa), with stress control
  bool stress_cycles = false;      // control = "stress": the axial stress cycles
  double failure_strain = 0.05;    // stress control: the test ends where |axial strain| passes it
  int cycles = 2;                  // full cycles per amplitude; the last one is measured
  int steps_per_cycle = 2000;      // slower than strain_rate where a cycle would be shorter
  int points_per_cycle = 200;      // rows of history.csv per cycle
  // direct_shear
  double shear_velocity = 0.0;    // m/s of the upper frame (default 0.02 x the box height)
  double max_displacement = 0.0;  // m (default 0.1 x the box length)
  double frame_gap = 0.0;         // m: the upper frame lifted off the lower one
};

struct TriaxialSettings;

// Reads the [loading] table of an element test into `s` (its confining stresses, rates,
// damping, servo and history settings, and the program of `s.element`).
void read_loading(TableReader& loading, TriaxialSettings& s);

}  // namespace geodem
