// Materials and the contact law of each material pair.
// A material names its contact law and parameters; the pair table resolves, once
// at set-up, the parameters of every (material, material) and (material, wall)
// pair so the force loop only reads a small flat table: no virtual call per contact.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace geodem {

enum class LawKind : std::uint8_t {
  kLinear,  // kn, kt constant or from a contact modulus; Coulomb friction
  kHertz,   // Hertz normal, Mindlin no-slip tangential; Coulomb friction
};

struct Material {
  std::string name;
  double density = 2600.0;
  LawKind law = LawKind::kLinear;
  // Linear law: either constant stiffnesses (kn > 0) or a contact modulus (young).
  double kn = 0.0;                  // N/m (3D), N/m per m (2D)
  double kt = -1.0;                 // < 0: kt_over_kn * kn
  double young = 0.0;               // Pa; linear: kn = 2 E r1 r2/(r1+r2); Hertz: Young's modulus
  double kt_over_kn = 0.5;          // linear law with modulus
  double poisson = 0.25;            // Hertz-Mindlin
  double friction = 0.5;            // Coulomb coefficient (tan of the friction angle)
  double restitution = 1.0;         // normal coefficient of restitution (1: no viscous damping)
  bool tangential_damping = false;  // tangential dashpot with the normal coefficient
  // Rolling and twisting resistance (docs/physics.md, "Rolling resistance"): moment springs
  // of stiffness rolling_stiffness x kt x R^2, limited to friction x fn x R.
  double rolling_friction = 0.0;   // eta_r (dimensionless)
  double twisting_friction = 0.0;  // eta_t, 3D only
  double rolling_stiffness = 1.0;  // dimensionless factor on kt R^2
  // Contact cohesion (bonds; docs/physics.md, "Cohesion"): tensile and shear strength,
  // stresses (Pa) scaled by the contact size, or forces (N; N/m in 2D) when
  // cohesion_as_force. Linear law only.
  double normal_cohesion = 0.0;
  double shear_cohesion = 0.0;
  bool cohesion_as_force = false;
};

// Damping ratio of a linear spring-dashpot that gives restitution e:
// beta = -ln e / sqrt(ln^2 e + pi^2), so c = 2 beta sqrt(m* kn).
inline double damping_ratio(double e) {
  if (e >= 1.0) return 0.0;
  const double l = std::log(e);
  return -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
}

// Resolved parameters of one pair; the force kernels read only this.
struct PairLaw {
  LawKind law = LawKind::kLinear;
  bool constant_stiffness = false;
  double kn = 0.0, kt = 0.0;    // constant stiffness
  double e1r = 0.0, e2r = 0.0;  // contact moduli of the two sides (modulus form)
  double kt_over_kn = 0.5;
  // 2D: stiffness per metre of thickness from the contact modulus (see linear_kn).
  bool per_unit_thickness = false;
  double estar = 0.0, gstar = 0.0;  // Hertz-Mindlin effective moduli
  double mu = 0.0;                  // Coulomb coefficient
  double beta = 0.0;                // viscous damping ratio from the restitution
  double hertz_damp = 0.0;          // hertz_damping(beta) (LIGGGHTS/Tsuji form)
  bool tangential_damping = false;
  double roll_mu = 0.0, twist_mu = 0.0, roll_kr = 1.0;
  double bond_tension = 0.0, bond_shear = 0.0;
  bool bond_as_force = false;

  bool rolling() const { return roll_mu > 0.0 || twist_mu > 0.0; }
  // The Hertz law's dashpot factor for a damping ratio beta (Tsuji, LIGGGHTS): gamma_n =
  // 2 sqrt(5/6) beta sqrt(Sn m*), Sn = 2 E* sqrt(R* delta) (contacts/contact_law.hpp).
  static double hertz_damping(double beta) { return 2.0 * std::sqrt(5.0 / 6.0) * beta; }
  bool cohesive() const { return bond_tension > 0.0 || bond_shear > 0.0; }
  // Lever of the rolling moment: R = r1 r2/(r1 + r2) between grains, r1 against a wall
  // (r2 = kWallRadius).
  static double rolling_radius(double r1, double r2) {
    return std::isinf(r2) ? r1 : r1 * r2 / (r1 + r2);
  }
  // Stiffness of the rolling (and twisting) moment springs, roll_kr kt R^2.
  double rolling_stiffness(double kt_value, double r1, double r2) const {
    const double r = rolling_radius(r1, r2);
    return roll_kr * kt_value * r * r;
  }
  // Bond strengths as forces: a stress times the contact size pi r_min^2 (3D) or
  // 2 r_min per metre of thickness (2D), yade's normalised cohesion; or given as forces.
  double bond_scale(double r1, double r2) const {
    if (bond_as_force) return 1.0;
    const double r = std::min(r1, r2);
    return per_unit_thickness ? 2.0 * r : std::numbers::pi * r * r;
  }

  // Normal stiffness of the linear law for grain radii r1, r2 (r2 = r1 against a wall).
  // 3D: kn = 2 E1 r1 E2 r2/(E1 r1 + E2 r2), i.e. 2 E r1 r2/(r1 + r2) for one material (N/m).
  // 2D (per metre of thickness): the same divided by the pair's mean radius, so that
  // kn = E for equal grains (N/m per m = Pa) and overlaps/radius do not depend on the
  // grain size, as in 3D.
  double linear_kn(double r1, double r2) const {
    if (constant_stiffness) return kn;
    const double a = e1r * r1, b = e2r * r2;
    const double k = 2.0 * a * b / (a + b);
    return per_unit_thickness ? k / (0.5 * (r1 + r2)) : k;
  }
  double linear_kt(double kn_value) const {
    return constant_stiffness ? kt : kt_over_kn * kn_value;
  }
};

// Stands for a wall's radius where a law needs the partner's curvature (rolling lever).
inline constexpr double kWallRadius = std::numeric_limits<double>::infinity();

// Combines two materials (the second may be a wall's) into pair parameters.
// Mixing rules (yade's FrictMat convention): friction = min, restitution = min,
// contact modulus in series; Hertz: 1/E* = sum (1-nu^2)/E, 1/G* = sum 2(2-nu)(1+nu)/E.
PairLaw combine(const Material& a, const Material& b);

}  // namespace geodem
