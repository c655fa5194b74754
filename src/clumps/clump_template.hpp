// Clump templates: the shape of a rigid grain made of overlapping or touching
// discs (2D) / spheres (3D), and the mass properties of their union.
//
// Mass properties are integrated over the union, so overlaps count once. The method
// (column integration, in clump_template.cpp) is exact along one axis and uses the
// midpoint rule across the others; its accuracy is stated there and checked in
// tests/unit/clump_mass_test.cpp against closed-form values.
#pragma once

#include <string>
#include <vector>

#include "base/dim.hpp"

namespace geodem {

template <int D>
struct ClumpTemplate {
  using Vec = typename Dim<D>::Vec;
  std::string name;
  std::vector<Vec> centre;     // member centres, any frame (unit scale)
  std::vector<double> radius;  // member radii (unit scale)
};

// Volume (area per unit thickness in 2D), centroid and second moment of the union
// of the members, for unit density.
template <int D>
struct MassProperties {
  using Vec = typename Dim<D>::Vec;
  using Tensor = typename Dim<D>::Tensor;
  double volume = 0.0;
  Vec centroid = Vec::Zero();
  // About the centroid, per unit density: 3D the inertia tensor; 2D the second-moment
  // matrix of the area (its trace is the polar moment of inertia).
  Tensor inertia = Tensor::Zero();
};

// `columns`: number of integration columns across the widest extent of the union
// (per axis in 3D). The default gives a relative error below 1e-5 on the volume
// and inertia of the shapes tested (docs/physics.md, "Clumps").
template <int D>
MassProperties<D> union_mass_properties(const std::vector<typename Dim<D>::Vec>& centre,
                                        const std::vector<double>& radius, int columns = 0);

// A template resolved for use: members in the principal frame of the union (centroid
// at the origin, principal axes along x, y(, z)), with its mass properties per unit
// density. Scaling by s multiplies offsets and radii by s, volume by s^D and the
// principal moments by s^(D+2).
template <int D>
struct ResolvedClump {
  using Vec = typename Dim<D>::Vec;
  std::string name;
  std::vector<Vec> offset;  // member centres in the body frame
  std::vector<double> radius;
  double volume = 0.0;
  // Principal second moments per unit density: a scalar (polar) in 2D, one per axis in 3D.
  typename Dim<D>::Rot principal = Dim<D>::zero_rot();
  double bounding_radius = 0.0;  // of the members about the centroid
};

template <int D>
ResolvedClump<D> resolve_clump(const ClumpTemplate<D>& t);

// Built-in templates by name: "sphere" / "disc" (one member), "pair" (two equal touching
// members), "pair_0.9" (the paper's grain: touching members of radii 1 and 0.9).
// Returns false for an unknown name.
template <int D>
bool builtin_clump_template(const std::string& name, ClumpTemplate<D>& out);
std::vector<std::string> builtin_clump_template_names();

}  // namespace geodem
