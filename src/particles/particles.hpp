// Grains stored as a structure of arrays: each property is one contiguous array,
// so the hot loops stream only what they read. No per-grain heap objects.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "base/dim.hpp"

namespace geodem {

enum ParticleFlags : std::uint8_t {
  kFixed = 1u << 0,        // not integrated: keeps its prescribed velocity
  kClumpMember = 1u << 1,  // moved by its clump (clumps/clumps.hpp), not integrated alone
  // A copy of a grain another rank owns (domain/slab_domain.hpp): its state comes from there
  // after each step; it has no wall contacts and no contacts with other ghosts here.
  kGhost = 1u << 2,
};

template <int D>
struct Particles {
  using Vec = typename Dim<D>::Vec;
  using Rot = typename Dim<D>::Rot;
  using Orient = typename Dim<D>::Orient;

  // Hot state, read or written every step.
  std::vector<Vec> pos;
  std::vector<Vec> vel;  // at the half step t - dt/2 between integrations
  std::vector<Rot> angvel;
  std::vector<Vec> force;  // resultant of contact forces this step (gravity added at integration)
  std::vector<Rot> torque;
  std::vector<double> radius;
  std::vector<double> inv_mass;
  std::vector<double> inv_inertia;
  std::vector<std::uint16_t> material;
  std::vector<std::uint8_t> flags;
  // Warm state: needed by the neighbour list and the outputs.
  std::vector<Vec> pos_at_build;  // position when the neighbour list was last built
  // Orientations: empty unless tracked (World::track_orientation), then one per grain.
  std::vector<Orient> orient;
  std::vector<std::uint32_t> id;  // stable user-facing identifier
  std::uint32_t next_id = 0;      // unique even after grains were removed
  // Clump membership: empty while the world has no clump, then one entry per grain:
  // the clump index (kNoClump for a free grain) and the centre in the clump's body frame.
  std::vector<std::uint32_t> clump;
  std::vector<Vec> body_offset;
  // Renumbering keeps every array in its buffer (see permute): set while something holds
  // pointers into the arrays across steps (the Python module's views). Not state.
  bool stable_buffers = false;

  std::size_t size() const { return pos.size(); }

  void reserve(std::size_t n) {
    pos.reserve(n), vel.reserve(n), angvel.reserve(n), force.reserve(n), torque.reserve(n);
    radius.reserve(n), inv_mass.reserve(n), inv_inertia.reserve(n), material.reserve(n);
    flags.reserve(n), pos_at_build.reserve(n), id.reserve(n);
  }

  // Adds a grain of the given density; returns its index.
  std::size_t add(const Vec& x, double r, double density, std::uint16_t mat,
                  const Vec& v = Vec::Zero(), Rot w = Dim<D>::zero_rot(), bool fixed = false) {
    const double m = density * Dim<D>::volume(r);
    pos.push_back(x);
    vel.push_back(v);
    angvel.push_back(w);
    force.push_back(Vec::Zero());
    torque.push_back(Dim<D>::zero_rot());
    radius.push_back(r);
    // A fixed grain behaves as infinitely heavy in contacts (like a wall).
    inv_mass.push_back(fixed ? 0.0 : 1.0 / m);
    inv_inertia.push_back(fixed ? 0.0 : 1.0 / (Dim<D>::inertia_factor() * m * r * r));
    material.push_back(mat);
    flags.push_back(fixed ? kFixed : 0);
    pos_at_build.push_back(x);
    if (!orient.empty()) orient.push_back(Dim<D>::identity());
    id.push_back(next_id++);
    if (!clump.empty()) {
      clump.push_back(0xffffffffu);
      body_offset.push_back(Vec::Zero());
    }
    return pos.size() - 1;
  }

  bool fixed(std::size_t i) const { return flags[i] & kFixed; }
  bool member(std::size_t i) const { return flags[i] & kClumpMember; }
  // A body integrated on its own: neither fixed nor a clump member.
  bool free_body(std::size_t i) const { return !(flags[i] & (kFixed | kClumpMember | kGhost)); }

  // Reorders every array: new index k holds the grain that had index order[k]. An
  // order shorter than the grains keeps only those it lists (removal).
  void permute(const std::vector<std::uint32_t>& order) {
    const std::size_t n = size();
    // A renumbering (order as long as the arrays) moves every array in place, cycle by
    // cycle: a new array beside the old one was a list build's peak of memory (24 bytes a
    // grain for a 3-vector, docs/performance.md "Memory"), and the buffers stay those that
    // views may hold (stable_buffers: the Python module's numpy arrays).
    std::vector<bool> placed;
    auto apply = [&](auto& v) {
      if (order.size() == n && v.size() == n) {
        placed.assign(n, false);
        for (std::size_t first = 0; first < n; ++first) {
          if (placed[first]) continue;
          auto held = v[first];
          for (std::size_t k = first;;) {
            placed[k] = true;
            const std::size_t from = order[k];
            if (from == first) {
              v[k] = held;
              break;
            }
            v[k] = v[from];
            k = from;
          }
        }
        return;
      }
      // A removal: with stable_buffers the result is copied back into the same buffers (never
      // larger: no reallocation), so that the views keep pointing at live memory; else the
      // new arrays replace the old (one copy less).
      std::remove_reference_t<decltype(v)> out(order.size());
      for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
      if (stable_buffers)
        v.assign(out.begin(), out.end());
      else
        v.swap(out);
    };
    apply(pos), apply(vel), apply(angvel), apply(radius);
    // The step gives the force and torque arrays back during a list build (world/step.cpp).
    if (!force.empty()) apply(force), apply(torque);
    apply(inv_mass), apply(inv_inertia), apply(material), apply(flags);
    if (!pos_at_build.empty()) apply(pos_at_build);  // (likewise given back)
    if (!orient.empty()) apply(orient);
    apply(id);
    if (!clump.empty()) apply(clump), apply(body_offset);
  }
};

}  // namespace geodem
