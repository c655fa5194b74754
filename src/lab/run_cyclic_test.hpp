// The cyclic triaxial test's program (docs/element_tests.md): for each amplitude, a quarter
// cycle up to +A, `cycles` loops +A -> -A -> +A, and back to 0, the lateral axes at the
// confining stress. Strain control drives the axial strain at a rate and turns where the
// strain reaches the amplitude; stress control ramps the axial stress target linearly in
// time (the servo follows it) and turns where the ramp reaches the amplitude of q.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "base/text.hpp"
#include "io/step_loop.hpp"
#include "lab/element_drives.hpp"

namespace geodem {

template <class Lab>
void install_element_drives(Lab& lab);  // lab/run_element_test.hpp

// Cyclic: the axial strain (or q) the loading heads for after `turn` turning points: +A, -A, ...,
// +A (after `cycles` loops), then back to 0. Even turns go up (compression), odd ones down.
inline double cycle_target(std::uint64_t turn, double amplitude, int cycles) {
  if (turn == 2 * static_cast<std::uint64_t>(cycles) + 1) return 0.0;
  return turn % 2 == 0 ? amplitude : -amplitude;
}

// Cyclic: the rate of this amplitude: the test's strain rate, or slower where a cycle would
// take fewer than steps_per_cycle steps (a small amplitude); with stress control, the q rate
// of a cycle of steps_per_cycle steps, from q = 0.
// Stress control: the axial servo's target, moved without restarting its integral term.
template <class Lab>
void set_axial_target(Lab& lab, double target) {
  constexpr int D = Lab::kDim;
  if (lab.box.periodic)
    std::static_pointer_cast<CellServo<D>>(lab.servos[0])->set_target(D - 1, target);
  else
    std::static_pointer_cast<StressServo<D>>(lab.servos[D - 1])->set_target(target);
}

template <class Lab>
void begin_amplitude(Lab& lab) {
  auto& e = lab.element;
  const auto& p = lab.s.element;
  const double a = p.amplitudes[e.stage];
  e.turn = 0, e.path = 0.0, e.next_record = 0.0;
  constexpr int D = Lab::kDim;
  e.last_strain = lab.box.strain(lab.w, D - 1, e.ref);
  e.last_gamma = e.last_strain;
  for (int k = 0; k < D - 1; ++k) e.last_gamma -= lab.box.strain(lab.w, k, e.ref) / (D - 1);
  const double cycle_rate = 4.0 * a / (p.steps_per_cycle * lab.w.dt);
  e.rate = p.stress_cycles ? cycle_rate : std::min(lab.s.strain_rate, cycle_rate);
  e.q_target = 0.0;
}

template <class Lab>
void run_cycles(Lab& lab) {
  constexpr int D = Lab::kDim;
  auto& e = lab.element;
  const auto& p = lab.s.element;
  const std::uint64_t last_turn = 2 * static_cast<std::uint64_t>(p.cycles) + 1;
  // Shear stress and strain of the loop integral: tau = q / 2, gamma = eps_a - eps_r.
  const auto tau_gamma = [&](double& eps) {
    const auto [sa, sl] = axial_and_lateral(lab.w, lab.box);
    eps = lab.box.strain(lab.w, D - 1, e.ref);
    double er = 0.0;
    for (int k = 0; k < D - 1; ++k) er += lab.box.strain(lab.w, k, e.ref) / (D - 1);
    return std::array<double, 4>{0.5 * (sa - sl), eps - er, sa, sl};
  };
  while (e.stage < p.amplitudes.size()) {
    const double amp = p.amplitudes[e.stage];
    const double every = 4.0 * amp / p.points_per_cycle;
    step_loop(
        lab.w, lab.total_steps, [&] { return e.turn <= last_turn; },
        [&] { return e.path + 2.0 * e.rate * lab.w.dt >= e.next_record; },
        [&] {
          // This step's stresses were summed in the configuration it started from: they pair
          // with the strains before its deformation (a pairing one step off would add a loop
          // area of about -2 / (pi steps_per_cycle) to the damping ratio).
          double eps = 0.0;
          const auto [tau, gamma_now, sa, sl] = tau_gamma(eps);
          const double gamma = e.last_gamma, eps_then = e.last_strain;
          const double target = cycle_target(e.turn, amp, p.cycles);
          bool reached;
          if (p.stress_cycles) {
            // The ramp moves on by a step; the servo follows it from the next step.
            const double before = e.q_target, dq = e.rate * lab.w.dt;
            e.q_target =
                e.turn % 2 == 0 ? std::min(target, before + dq) : std::max(target, before - dq);
            e.path += std::abs(e.q_target - before);
            set_axial_target(lab, lab.sigma3() + e.q_target);
            // The turn waits, the target held, until q itself is within 1 % of the amplitude
            // of it: a stiff loop's servo follows the ramp, a soft one's lags at its rate limit.
            reached = e.q_target == target && std::abs(2.0 * tau - target) <= 0.01 * amp;
          } else {
            e.path += std::abs(eps - e.last_strain);
            reached = e.turn % 2 == 0 ? eps >= target : eps <= target;
          }
          e.last_strain = eps, e.last_gamma = gamma_now;
          if (p.stress_cycles && std::abs(eps) > p.failure_strain) {
            // The sample cannot carry this amplitude: it strains without bound (it fails, in
            // extension or compression); the amplitudes measured so far are the results.
            e.warning = cat("the sample failed at the q amplitude ", amp, " Pa: |axial strain| ",
                            std::abs(eps), " passed loading.failure_strain after ", e.turn,
                            " turning points");
            e.stage = p.amplitudes.size();
            return true;
          }
          e.loop.add(tau, gamma);
          if (lab.w.measure_this_step && e.path >= e.next_record) {
            while (e.next_record <= e.path) e.next_record += every;
            lab.history_row({static_cast<double>(e.stage), static_cast<double>((e.turn + 1) / 2),
                             static_cast<double>(lab.w.step), lab.w.time, eps, eps - gamma_now,
                             gamma_now, sa, sl, sa - sl, (sa + (D - 1) * sl) / D, void_ratio(lab),
                             unbalanced_force_ratio(lab.w)});
            lab.progress.update(cat("cyclic amplitude ", e.stage + 1, "/", p.amplitudes.size()),
                                lab.w.step, lab.w.time,
                                static_cast<double>(e.turn) / static_cast<double>(last_turn + 1),
                                "q " + format_sig(sa - sl) + " Pa");
          }
          if (!reached) return false;
          if (e.turn % 2 == 0) {  // at +A: a loop closes, the next one starts
            if (e.loop.started) e.loops.push_back(e.loop.result());
            e.loop.started = 0;
            if (e.turn + 1 < last_turn)
              e.loop.start(tau, gamma), e.loop.turn_high(tau, gamma, eps_then);
          } else if (e.turn != last_turn) {  // at -A
            e.loop.turn_low(tau, gamma, eps_then);
          }
          ++e.turn;
          if (e.turn <= last_turn) install_element_drives(lab);
          return false;
        },
        [&] { return lab.after_step(); });
    if (lab.s.vtk) lab.vtk.write(lab.w);
    if (e.stage >= p.amplitudes.size()) break;  // failed
    if (++e.stage < p.amplitudes.size()) {
      begin_amplitude(lab);
      install_element_drives(lab);
    }
  }
}

}  // namespace geodem
