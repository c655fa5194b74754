// What crosses between the ranks of a decomposed domain (domain/slab_domain.hpp), as plain
// records packed into byte buffers: a grain's state, and the history of a contact between two
// grains or between a grain and a wall. (The per-step update of a ghost packs its position,
// velocity, angular velocity and, if tracked, orientation: SlabDomain::after_integration.)
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "base/dim.hpp"
#include "base/state_archive.hpp"
#include "clumps/clumps.hpp"
#include "contacts/neighbour_list.hpp"
#include "domain/domain_comm.hpp"
#include "particles/particles.hpp"

namespace geodem {

template <int D>
struct GrainRecord {
  typename Dim<D>::Vec pos, vel, pos_at_build, body_offset;
  typename Dim<D>::Rot angvel;
  typename Dim<D>::Orient orient;
  double radius, inv_mass, inv_inertia;
  std::uint64_t key;  // the grain's place in every rank's order (domain/slab_domain.hpp)
  std::uint32_t id;
  std::uint32_t clump;  // a member's clump by the clump's id (not its index), else kNoClump
  std::uint16_t material;
  std::uint8_t flags;

  // `clump_id`: the id of the grain's clump, or kNoClump.
  static GrainRecord of(const Particles<D>& P, std::size_t i, std::uint64_t key,
                        std::uint32_t clump_id) {
    GrainRecord g;
    g.key = key;
    g.pos = P.pos[i], g.vel = P.vel[i], g.pos_at_build = P.pos_at_build[i];
    g.body_offset = P.body_offset.empty() ? Dim<D>::Vec::Zero() : P.body_offset[i];
    g.angvel = P.angvel[i];
    g.orient = P.orient.empty() ? Dim<D>::identity() : P.orient[i];
    g.radius = P.radius[i], g.inv_mass = P.inv_mass[i], g.inv_inertia = P.inv_inertia[i];
    g.id = P.id[i], g.clump = clump_id, g.material = P.material[i], g.flags = P.flags[i];
    return g;
  }
  // Appends the grain to P as an owned grain; a member's clump index is left as the clump's id
  // (the caller maps ids to indices).
  void append_to(Particles<D>& P) const {
    P.pos.push_back(pos), P.vel.push_back(vel), P.angvel.push_back(angvel);
    P.force.push_back(Dim<D>::Vec::Zero()), P.torque.push_back(Dim<D>::zero_rot());
    P.radius.push_back(radius), P.inv_mass.push_back(inv_mass),
        P.inv_inertia.push_back(inv_inertia);
    P.material.push_back(material), P.flags.push_back(static_cast<std::uint8_t>(flags & ~kGhost));
    P.pos_at_build.push_back(pos_at_build), P.id.push_back(id);
    if (clump != kNoClump || !P.clump.empty()) {
      P.clump.resize(P.size() - 1, kNoClump),
          P.body_offset.resize(P.size() - 1, Dim<D>::Vec::Zero());
      P.clump.push_back(clump), P.body_offset.push_back(body_offset);
    }
  }
};

// A clump's state, keyed by its id: it travels with its members when its centre changes
// ranks, and as a ghost clump with ghost members.
template <int D>
struct ClumpRecord {
  typename Dim<D>::Vec pos, vel;
  typename Dim<D>::Rot angvel, angmom, inertia, inv_inertia;
  typename Dim<D>::Orient orient;
  Eigen::Matrix<double, D, D> rotation;
  double inv_mass, volume;
  std::uint32_t id;
  std::uint8_t held;

  static ClumpRecord of(const Clumps<D>& C, std::size_t c) {
    return {C.pos[c],    C.vel[c],      C.angvel[c],
            C.angmom[c], C.inertia[c],  C.inv_inertia[c],
            C.orient[c], C.rotation[c], C.inv_mass[c],
            C.volume[c], C.id[c],       C.held.empty() ? std::uint8_t{0} : C.held[c]};
  }
  void append_to(Clumps<D>& C) const {
    C.pos.push_back(pos), C.vel.push_back(vel), C.angvel.push_back(angvel);
    C.angmom.push_back(angmom), C.orient.push_back(orient), C.rotation.push_back(rotation);
    C.force.push_back(Dim<D>::Vec::Zero()), C.torque.push_back(Dim<D>::zero_rot());
    C.inv_mass.push_back(inv_mass), C.inertia.push_back(inertia);
    C.inv_inertia.push_back(inv_inertia), C.volume.push_back(volume), C.id.push_back(id);
    if (held || !C.held.empty()) {
      C.held.resize(C.size() - 1, 0);
      C.held.push_back(held);
    }
  }
};

// A grain-grain contact's history, keyed by the grains' ids, a < b: the spring and moment
// springs as the list holds them for a row of grain a.
template <int D>
struct PairRecord {
  std::uint32_t a, b;
  TangentSpring<D> spring;
  ContactExtra<D> extra;
};

template <int D>
struct WallRecord {
  std::uint32_t id, wall;
  TangentSpring<D> spring;
  ContactExtra<D> extra;
};

// A grain-spar contact's tangential spring: grain id, element index (every rank holds the
// whole chains).
template <int D>
struct SparRecord {
  std::uint32_t id, element;
  TangentSpring<D> spring;
};

// Records are stored as their bytes in checkpoints too (base/state_archive.hpp).
template <int D>
struct IsPlainData<PairRecord<D>> : std::true_type {};
template <int D>
struct IsPlainData<WallRecord<D>> : std::true_type {};
template <int D>
struct IsPlainData<SparRecord<D>> : std::true_type {};

// What a checkpoint of a decomposed run keeps besides the world's state (whose grains are
// saved in key order, without ghosts, and whose neighbour list is empty): the grid of the
// keys and how often they are retaken, each grain's key, and the contact history as records.
template <int D>
struct DomainCheckpoint {
  typename Dim<D>::Vec grid_lo = Dim<D>::Vec::Zero();
  std::array<std::uint64_t, 3> grid_dims{1, 1, 1};
  std::int64_t sort_every = 0;
  // The skin, ghost width (the keys' cell size) and clump reach of the run: taken again as
  // they were, not from the grains now (a run that removed grains would find others).
  double skin = 0.0, ghost_width = 0.0, extent = 0.0;
  // The keys' block that starts a force slab (SlabDomain: 0, one slab a rank).
  std::uint64_t key_block = 0;
  std::vector<std::uint64_t> keys;
  std::vector<PairRecord<D>> pairs;
  std::vector<WallRecord<D>> walls;
  std::vector<SparRecord<D>> spars;
  template <class Archive>
  void visit(Archive& a) {
    a(grid_lo), a(grid_dims), a(sort_every), a(skin), a(ghost_width), a(extent), a(key_block);
    a(keys), a(pairs), a(walls), a(spars);
  }
};

// Arrays of records appended to a buffer as a count and their bytes, read back in order.
template <typename T>
void put_records(Bytes& out, const std::vector<T>& v) {
  const std::uint64_t n = v.size();
  const std::size_t at = out.size();
  out.resize(at + sizeof n + n * sizeof(T));
  std::memcpy(out.data() + at, &n, sizeof n);
  if (n > 0)
    std::memcpy(out.data() + at + sizeof n, static_cast<const void*>(v.data()), n * sizeof(T));
}
// Appends the next array of records to `v` (whose capacity is kept between calls).
template <typename T>
void append_records(const Bytes& in, std::size_t& at, std::vector<T>& v) {
  std::uint64_t n = 0;
  if (in.size() < at + sizeof n) throw std::runtime_error("domain message truncated");
  std::memcpy(&n, in.data() + at, sizeof n);
  at += sizeof n;
  if ((in.size() - at) / sizeof(T) < n) throw std::runtime_error("domain message truncated");
  const std::size_t first = v.size();
  v.resize(first + n);
  if (n > 0) std::memcpy(static_cast<void*>(v.data() + first), in.data() + at, n * sizeof(T));
  at += n * sizeof(T);
}
}  // namespace geodem
