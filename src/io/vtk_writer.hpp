// VTK XML output for ParaView: grains as .vtu point clouds (radius, velocity,
// angular velocity, force, id), walls as .vtp polygons/lines, and a .pvd time index
// that lists both. Binary data in raw appended form (compact and fast).
#pragma once

#include <string>
#include <vector>

#include "world/world.hpp"

namespace geodem {

// With `reference` (positions by grain id, measure/displacement.hpp), also each grain's
// displacement since it (NaN for a grain added after it).
template <int D>
void write_particles_vtu(const std::string& path, const World<D>& world,
                         const std::vector<typename Dim<D>::Vec>* reference = nullptr);

// The same for the contacts of write_contacts_vtp (a .pvtp).
void write_contacts_pvtp(const std::string& path, const std::vector<std::string>& pieces);

// The index of a frame written in pieces (one .vtu of write_particles_vtu per rank of a
// decomposed domain, file names relative to the .pvtu's folder).
void write_particles_pvtu(const std::string& path, const std::vector<std::string>& pieces,
                          bool displacement);

// Planes are drawn as squares (3D) or segments (2D) of the given half size, centred
// on the grains' centroid projected onto the plane (or on `grains_centre` when given).
template <int D>
void write_walls_vtp(const std::string& path, const World<D>& world, double half_size,
                     const typename Dim<D>::Vec* grains_centre = nullptr);

// Spar chains as polylines: node velocity, element tension, stiffness and chain index.
template <int D>
void write_spars_vtp(const std::string& path, const World<D>& world);

// The grain-grain contacts as lines between grain centres (force chains in ParaView: a Tube
// filter sized by force): per line normal_force (N; N/m in 2D; negative for a bond in
// tension), tangential_force (vector) and its magnitude, force (magnitude of the whole
// elastic force), normal, overlap, bonded; per point the grain radius.
template <int D>
void write_contacts_vtp(const std::string& path, const World<D>& world);

// The periodic cell's edges as .vtp lines (4 in 2D, 12 in 3D), each carrying the cell's
// average stress tensor (compression positive), for ParaView.
template <int D>
void write_cell_vtp(const std::string& path, const World<D>& world);

// The .pvd index: part 0 grains, part 1 walls, part 2 spar chains, part 3 contacts, part 4
// the periodic cell.
class PvdIndex {
 public:
  struct Entry {
    double time;
    std::string file;
    int part;
  };
  explicit PvdIndex(std::string path) : path_(std::move(path)) {}
  void add(double time, const std::string& file, int part);
  void write() const;
  const std::vector<Entry>& entries() const { return entries_; }
  std::vector<Entry>& entries() { return entries_; }

 private:
  std::string path_;
  std::vector<Entry> entries_;
};

}  // namespace geodem
