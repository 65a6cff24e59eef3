#pragma once
/// \file stability.hpp
/// Bloch-wave analysis of the infinite hexagonal lattice (physics.md sections 4-5): the
/// dynamical matrix over the Brillouin zone, for the rotation model (3x3: ux, uy, theta) or
/// the local-strain model (2x2: ux, uy). Gives stability (omega^2 >= 0 everywhere) and the
/// critical time step of central differences, dt_c = 2 / omega_max.

#include "hexdem/solver/material.hpp"

namespace hexdem::solver {

struct BlochResult {
  bool stable = true;
  double omega2_min = 0;  ///< smallest omega^2 over the zone [1/s^2] (negative: unstable)
  double omega2_max = 0;  ///< largest omega^2 [1/s^2]
  double dt_critical = 0; ///< 2 / sqrt(omega2_max) [s]
  double growth_time = 0; ///< e-folding time of the fastest growing mode if unstable [s]
};

/// Bloch analysis for springs K (per unit thickness), density rho, disk radius r, cell-area
/// mass m = rho 2 sqrt(3) r^2 (per unit thickness), I = m r^2 / 2, on an nk x nk k-grid.
BlochResult bloch_analysis(const SpringConstants& K, double rho, double r, ShearModel model,
                           int nk = 48);

/// Eq. 24 of the paper, dt = 2 / sqrt(k_max / m), for comparison only (it is not conservative).
double eq24_time_step(const SpringConstants& K, double rho, double r);

}  // namespace hexdem::solver
