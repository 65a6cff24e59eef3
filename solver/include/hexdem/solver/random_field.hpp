#pragma once
/// \file random_field.hpp
/// Spatially correlated random strength ([random], docs/model.md "Random strength"): a
/// stationary Gaussian field with covariance exp(-d^2 / (2 l^2)), by the spectral method
/// (Shinozuka and Deodatis, Appl. Mech. Rev. 44 (1991) 191): g(x) = sqrt(2/N) sum_n
/// cos(k_n . x + phi_n), k_n drawn from the Gaussian spectrum N(0, I / l^2), phi_n uniform.
/// The factor exp(s g - s^2 / 2), s^2 = ln(1 + cov^2), is lognormal with mean 1 and coefficient
/// of variation cov. The field is evaluated at points in space, so it does not depend on the
/// lattice (its spacing or angle); the same seed gives the same field on every machine (a
/// portable generator, no std:: distributions). Lengths in m.

#include <cstdint>
#include <vector>

namespace hexdem::solver {

/// Number of Fourier modes of the field: its variance is exact, its distribution
/// Gaussian within the central limit for this many terms.
constexpr int kRandomFieldModes = 256;

/// Factor of the field at the points (x[k], y[k]) [m]. `stream` draws an independent field from
/// the same seed (0: the strength field, 1: the stiffness field).
std::vector<double> lognormal_field(const std::vector<double>& x, const std::vector<double>& y, std::int64_t seed,
                                    double correlation_length, double cov, std::uint64_t stream = 0);

}  // namespace hexdem::solver
