// The loading programs of the element tests (docs/lab_tests.md), run by the triaxial kind's
// lab (lab/run_triaxial.cpp) once its sample is prepared and consolidated:
// - isotropic: every axis held at each mean stress of `stresses` in turn, until at rest;
// - oedometer: the axial stress held at each of `stresses`, the lateral axes fixed;
// - simple_shear: the periodic cell sheared, L_xn = shear_rate (x the first axis, n the
//   last), the normal axis at the consolidation stress (or fixed: constant volume), the
//   others fixed;
// - cyclic_triaxial: the axial strain cycled between +A and -A around the consolidated
//   state, the lateral axes at the confining stress, `cycles` loops per amplitude;
// - direct_shear: the box split at mid-height (lab/direct_shear_box.hpp), its upper
//   frame slid at shear_velocity, the plate held at the normal stress.
// The functions take the lab runner; its members: w, box, s, servos, element, total_steps,
// history, progress, vtk, run_until, after_step, porosity, sigma3.
#pragma once

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "base/text.hpp"
#include "controllers/axial_strain_rate.hpp"
#include "controllers/cell_servo.hpp"
#include "controllers/stress_servo.hpp"
#include "io/step_loop.hpp"
#include "lab/direct_shear_box.hpp"
#include "lab/element_drives.hpp"
#include "lab/element_test_state.hpp"
#include "lab/run_cyclic_test.hpp"
#include "measure/measurements.hpp"
#include "walls/lab_box.hpp"

namespace geodem {

template <class Lab>
void install_element_drives(Lab& lab) {
  constexpr int D = Lab::kDim;
  const auto& e = lab.element;
  const auto& p = lab.s.element;
  std::array<AxisDrive, D> d{};
  double shear = 0.0;
  switch (lab.s.kind) {
    case LabKind::kIsotropic:
      for (auto& a : d) a = {true, p.stresses[e.stage], 0.0};
      break;
    case LabKind::kOedometer:
      d[D - 1] = {true, p.stresses[e.stage], 0.0};
      break;
    case LabKind::kSimpleShear:
      if (!p.constant_volume) d[D - 1] = {true, lab.sigma3(), 0.0};
      shear = p.shear_rate;
      break;
    case LabKind::kCyclicTriaxial:
      for (int k = 0; k < D - 1; ++k) d[k] = {true, lab.sigma3(), 0.0};
      if (p.stress_cycles)
        d[D - 1] = {true, lab.sigma3() + e.q_target, 0.0};
      else
        d[D - 1].rate = (e.turn % 2 == 0 ? 1.0 : -1.0) * e.rate;
      break;
    case LabKind::kDirectShear:
      // The lips reach a tenth of the box length past the largest displacement.
      if (!shear_box_split(lab.w))
        split_shear_box(lab.w, lab.box, e.split, p.max_displacement + 0.1 * lab.box.size(lab.w).x(),
                        p.frame_gap);
      drive_upper_frame(lab.w, shear_frames(lab.box), p.shear_velocity);
      lab.w.controllers = {lab.servos[0]};
      return;
    case LabKind::kTriaxial:
      break;
  }
  drive_axes<D>(lab.w, lab.box, d, shear, lab.servos);
}

// A row of an isotropic or oedometer test; a point at rest is also kept for the results.
template <class Lab>
void stress_step_row(Lab& lab, double unbalanced, bool at_rest, double target) {
  constexpr int D = Lab::kDim;
  auto& e = lab.element;
  const auto [sa, sl] = axial_and_lateral(lab.w, lab.box);
  const double ea = lab.box.strain(lab.w, D - 1, e.ref);
  const double ev = lab.box.volumetric_strain(lab.w, e.ref);
  const double void_r = void_ratio(lab);
  lab.history_row({static_cast<double>(e.stage), static_cast<double>(lab.w.step), lab.w.time,
                   target, sa, sl, (sa + (D - 1) * sl) / D, sa - sl, ea, ev, void_r,
                   coordination_number(lab.w), unbalanced, at_rest ? 1.0 : 0.0});
  if (!at_rest) return;
  auto& p = e.steps;
  p.target.push_back(target), p.sigma_axial.push_back(sa), p.sigma_lateral.push_back(sl);
  p.axial_strain.push_back(ea), p.volumetric_strain.push_back(ev), p.void_ratio.push_back(void_r);
}

// After consolidation: the reference state, the first point, the first step's drives.
template <class Lab>
void begin_element_test(Lab& lab) {
  auto& e = lab.element;
  e = {};
  e.ref = lab.box.size(lab.w);
  e.porosity0 = lab.porosity();
  if (lab.s.kind == LabKind::kCyclicTriaxial) begin_amplitude(lab);
  if (lab.s.kind == LabKind::kDirectShear) {
    e.plate0 = lab.w.walls[lab.box.hi[Lab::kDim - 1]].point[Lab::kDim - 1];
    e.split = 0.5 * (lab.w.walls[lab.box.lo[Lab::kDim - 1]].point[Lab::kDim - 1] + e.plate0);
  }
  if (lab.s.kind == LabKind::kIsotropic || lab.s.kind == LabKind::kOedometer)
    stress_step_row(lab, unbalanced_force_ratio(lab.w), true, lab.sigma3());
  install_element_drives(lab);
}

template <class Lab>
void run_stress_steps(Lab& lab) {
  constexpr int D = Lab::kDim;
  auto& e = lab.element;
  const auto& stresses = lab.s.element.stresses;
  const bool iso = lab.s.kind == LabKind::kIsotropic;
  while (e.stage < stresses.size()) {
    const double target = stresses[e.stage];
    const auto on_target = [&] {
      for (int k = iso ? 0 : D - 1; k < D; ++k)
        if (std::abs(lab.box.stress(lab.w, k) - target) > lab.s.stress_tolerance * target)
          return false;
      return true;
    };
    const std::string name = cat("step ", e.stage + 1, "/", stresses.size(), " (", target, " Pa)");
    const bool met = lab.run_until(name, lab.s.stage_max_steps, 200, [&](double unb) {
      const bool rest = on_target() && unb < lab.s.unbalanced_tolerance;
      stress_step_row(lab, unb, rest, target);
      return rest;
    });
    if (!met) {
      if (!on_target())
        throw std::runtime_error(cat("the sample did not reach ", target, " Pa in ",
                                     lab.s.stage_max_steps,
                                     " steps; raise loading.stage_max_steps"));
      e.warning = cat("step ", e.stage + 1,
                      " ended on its stress with the unbalanced force above "
                      "the tolerance after loading.stage_max_steps");
      stress_step_row(lab, unbalanced_force_ratio(lab.w), true, target);
    }
    if (lab.s.vtk) lab.vtk.write(lab.w);
    if (++e.stage < stresses.size()) install_element_drives(lab);
  }
}

// Shears until `measure()` (the shear strain or displacement, growing at about `rate` per
// second) reaches `max`, with a row (`row()`) every max / history_points of it, written on a
// measuring step.
template <class Lab, class Measure, class Row>
void shear_to(Lab& lab, Measure&& measure, double max, double rate, Row&& row) {
  auto& e = lab.element;
  const double every = max / lab.s.history_points;
  step_loop(
      lab.w, lab.total_steps, [&] { return measure() < max; },
      [&] {
        const double next = measure() + 2.0 * rate * lab.w.dt;
        return next >= e.next_record || next >= max;
      },
      [&] {
        const double g = measure();
        if (lab.w.measure_this_step && (g >= e.next_record || g >= max)) {
          while (e.next_record <= g) e.next_record += every;
          row();
        }
        return false;
      },
      [&] { return lab.after_step(); });
}

// Simple shear: the shear strain is the cell's tilt, h_xn / h_nn.
template <class Lab>
double cell_shear_strain(const Lab& lab) {
  constexpr int n = Lab::kDim - 1;
  return lab.w.cell.h(0, n) / lab.w.cell.h(n, n);
}

// A point of a shear curve (the shear strain or displacement x, up to `max`), and the progress.
template <class Lab>
void add_shear_point(Lab& lab, const char* name, double x, double max, double tau, double sn,
                     double normal_strain, double phi, double void_r) {
  auto& c = lab.element.curve;
  c.shear_strain.push_back(x), c.shear_stress.push_back(tau), c.normal_stress.push_back(sn);
  c.normal_strain.push_back(normal_strain), c.phi_mobilised_deg.push_back(phi);
  c.void_ratio.push_back(void_r);
  const double tests = static_cast<double>(lab.s.confining_stresses.size());
  lab.progress.update(cat(name, lab.test + 1, "/", lab.s.confining_stresses.size()), lab.w.step,
                      lab.w.time, x / max, "tau/sigma_n " + format_sig(tau / sn),
                      (static_cast<double>(lab.test) + x / max) / tests);
}

template <class Lab>
void simple_shear_row(Lab& lab) {
  constexpr int D = Lab::kDim, n = D - 1;
  auto& e = lab.element;
  const auto sigma = cell_stress(lab.w);
  // Compression positive: the shear stress that resists a positive L_xn is -sigma_xn.
  const double tau = -sigma(0, n), sn = sigma(n, n), gamma = cell_shear_strain(lab);
  const auto principal =
      Eigen::SelfAdjointEigenSolver<typename Dim<D>::Tensor>(sigma, Eigen::EigenvaluesOnly)
          .eigenvalues();  // ascending
  const double s1 = principal[D - 1], s3 = principal[0];
  const double phi =
      std::asin(std::clamp((s1 - s3) / (s1 + s3), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  const double en = lab.box.strain(lab.w, n, e.ref), ev = lab.box.volumetric_strain(lab.w, e.ref);
  const double void_r = void_ratio(lab);
  lab.history_row({static_cast<double>(lab.test), static_cast<double>(lab.w.step), lab.w.time,
                   gamma, en, ev, sn, tau, tau / sn, s1, s3, phi, sigma.trace() / D, void_r,
                   coordination_number(lab.w), unbalanced_force_ratio(lab.w)});
  add_shear_point(lab, "simple shear ", gamma, lab.s.element.max_shear_strain, tau, sn, en, phi,
                  void_r);
}

template <class Lab>
void run_simple_shear(Lab& lab) {
  const double max = lab.s.element.max_shear_strain;
  shear_to(
      lab, [&] { return cell_shear_strain(lab); }, max, lab.s.element.shear_rate,
      [&] { simple_shear_row(lab); });
  lab.w.cell.vel_grad(0, Lab::kDim - 1) = 0.0;
}

// Direct shear: the upper frame's displacement is its left side's position.
template <class Lab>
double frame_displacement(const Lab& lab) {
  return lab.w.walls[shear_frames(lab.box).upper[0]].point[0];
}

// Grains whose centres lie outside both frames (the lips keep them in: 0).
template <class Lab>
std::size_t grains_outside_shear_box(const Lab& lab) {
  constexpr int v = Lab::kDim - 1;
  const auto& P = lab.w.particles;
  const auto size = lab.box.size(lab.w);
  const double u = frame_displacement(lab), length = size.x(), width = size[Lab::kDim == 3];
  const double top = lab.w.walls[lab.box.hi[v]].point[v], split = lab.element.split;
  std::size_t out = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.flags[i] & kGhost) continue;  // (counted by its owner)
    const double x = P.pos[i].x(), z = P.pos[i][v], shift = z > split ? u : 0.0;
    const bool off_width = Lab::kDim == 3 && (P.pos[i][1] < 0.0 || P.pos[i][1] > width);
    if (x < shift || x > length + shift || z < 0.0 || z > top || off_width) ++out;
  }
  return lab.w.domain ? lab.w.domain->count_over_ranks(out) : out;
}

template <class Lab>
void direct_shear_row(Lab& lab) {
  constexpr int v = Lab::kDim - 1;
  auto& e = lab.element;
  const auto size = lab.box.size(lab.w);
  const double u = frame_displacement(lab);
  // The stresses on the split plane's shrinking area (length - u, times the width in 3D); the
  // plate's over its own.
  const double area = (size.x() - u) * (Lab::kDim == 3 ? size[1] : 1.0);
  const double tau = shear_box_force(lab.w, lab.box, shear_frames(lab.box)) / area;
  const double sn = lab.w.walls[lab.box.hi[v]].normal_stress();
  const double rise = lab.w.walls[lab.box.hi[v]].point[v] - e.plate0;
  const double void_r = void_ratio(lab);
  lab.history_row({static_cast<double>(lab.test), static_cast<double>(lab.w.step), lab.w.time, u,
                   tau, sn, tau / sn, rise, void_r, coordination_number(lab.w),
                   unbalanced_force_ratio(lab.w)});
  add_shear_point(lab, "direct shear ", u, lab.s.element.max_displacement, tau, sn, -rise,
                  std::atan(tau / sn) * 180.0 / std::numbers::pi, void_r);
}

template <class Lab>
void run_direct_shear(Lab& lab) {
  shear_to(
      lab, [&] { return frame_displacement(lab); }, lab.s.element.max_displacement,
      lab.s.element.shear_velocity, [&] { direct_shear_row(lab); });
  drive_upper_frame(lab.w, shear_frames(lab.box), 0.0);
}

template <class Lab>
void run_element_test(Lab& lab) {
  switch (lab.s.kind) {
    case LabKind::kIsotropic:
    case LabKind::kOedometer:
      run_stress_steps(lab);
      break;
    case LabKind::kSimpleShear:
      run_simple_shear(lab);
      break;
    case LabKind::kCyclicTriaxial:
      run_cycles(lab);
      break;
    case LabKind::kDirectShear:
      run_direct_shear(lab);
      break;
    case LabKind::kTriaxial:
      break;
  }
}

// A finished element test's results (summary.json).
template <class Lab>
nlohmann::json element_test_results(const Lab& lab) {
  const auto& e = lab.element;
  nlohmann::json r;
  switch (lab.s.kind) {
    case LabKind::kIsotropic:
    case LabKind::kOedometer:
      r = stress_step_results(e.steps, lab.s.kind, Lab::kDim);
      break;
    case LabKind::kSimpleShear:
      r = simple_shear_results(e.curve);
      r["control"] = lab.s.element.constant_volume ? "constant_volume" : "constant_stress";
      break;
    case LabKind::kCyclicTriaxial:
      r = cyclic_results(lab.s.element.amplitudes, lab.s.element.cycles, e.loops,
                         lab.s.element.stress_cycles ? "q_amplitude" : "axial_strain_amplitude");
      r["control"] = lab.s.element.stress_cycles ? "stress" : "strain";
      r["confining_stress"] = lab.sigma3();
      break;
    case LabKind::kDirectShear:
      r = direct_shear_results(e.curve);
      r["grains_outside_box"] = grains_outside_shear_box(lab);
      break;
    case LabKind::kTriaxial:
      break;
  }
  r["porosity_initial"] = e.porosity0;
  r["grains"] = body_count(lab.w);
  r["steps"] = lab.w.step;
  if (!e.warning.empty()) r["warning"] = e.warning;
  return r;
}

}  // namespace geodem
