// The grains of a world as a text table that a scene reads back with [[particle_files]]:
// one row per grain, columns id x y [z] radius vx vy [vz] material, numbers written to
// round-trip exactly (17 significant digits).
#pragma once

#include <string>
#include <vector>

#include "materials/material.hpp"
#include "world/world.hpp"

namespace geodem {

// The column names written, in order (the `columns` to give [[particle_files]]).
std::vector<std::string> particle_table_columns(int dimension);

// Writes the table atomically (a crash leaves the old file or the new one, never half).
// `material` is the index of the grain's material in `materials`, listed in the header.
template <int D>
void write_particle_table(const std::string& path, const World<D>& world,
                          const std::vector<Material>& materials);

}  // namespace geodem
