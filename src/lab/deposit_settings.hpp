// Settings shared by the 2D lab kinds that deposit a soil by gravity and couple it to a
// geosynthetic sheet (pull-out, interface shear): the [soil] and [sheet] tables, read
// by one function each so that both kinds accept the same keys with the same checks.
#pragma once

#include <cstdint>
#include <string>

#include "clumps/grain_mix.hpp"
#include "io/toml_reader.hpp"
#include "materials/material.hpp"

namespace geodem {

struct DepositedSoil {
  Material soil, wall;
  GrainSpec grains;
  double radius = 0.01;  // mean grain scale (m): the radius of round grains
  double radius_fuzz = 0.25;
  double layer_thickness = 0.1;     // deposition layers (m)
  double settle_unbalanced = 0.01;  // a layer is at rest below this unbalanced force
  bool bonds = false;               // cohesive soil: bond the contacts after filling
  double bond_gap_tolerance = 0.0;
  double deposit_damping = 0.4;
  // Contact friction while the soil is deposited (< 0: the soil's own): lower friction
  // packs it denser, as the friction reduction of the triaxial test does.
  double deposit_friction_deg = -1.0;
  // Folder of stored deposits (lab/deposit_cache.hpp); empty: every run deposits its own.
  std::string deposit_cache;
};

struct SheetSettings {
  double stiffness_J = 1e5;     // N/m
  double element_length = 0.0;  // 0: the mean grain diameter
  double interface_friction_deg = 34.0;
  double mass_per_area = 0.5;  // kg/m^2
  double thickness = 0.002;    // m (contact radius of the elements is half of it)
  double bending = 0.0;        // N m/rad per m width at each node
  // The shape the bending stiffness returns the sheet to: flat (as off the roll; the
  // sheet is held in its laid shape until the soil around it is placed), or the shape it
  // was laid in (its rest turns then travel with the material as it is pulled).
  bool rest_flat = true;
  bool mass_scaling = true;       // raise node masses so the sheet does not set the time step
  double node_mass_factor = 0.0;  // > 0: this factor instead of the estimate (mass_scaling)
};

// [time] of these kinds: the automatic time step and the settling limit.
struct DepositTime {
  double dt_safety = 0.8;
  int dt_update_interval = 20;
  std::uint64_t max_settle_steps = 400'000;
};

// Reads [time] (optional).
void read_deposit_time(TableReader& root, DepositTime& t);

// Reads [soil] (required) and the [[templates]] it may name; the smooth wall material
// is derived from the soil's.
void read_deposited_soil(TableReader& root, DepositedSoil& s);

// Reads [sheet] (optional); lengths default from the grain radius.
void read_sheet(TableReader& root, double radius, SheetSettings& s);

}  // namespace geodem
