#pragma once
/// \file model_inl.hpp
/// Inline templates of model.hpp.

#include <cstddef>
#include <vector>

namespace hexdem::solver {

inline constexpr std::size_t kSumBlock = 4096;

template <class F>
double deterministic_sum(std::size_t n, F&& f, std::vector<double>& scratch) {
  const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
  if (scratch.size() < blocks) scratch.resize(blocks);
  double* part = scratch.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t b = 0; b < static_cast<std::ptrdiff_t>(blocks); ++b) {
    const std::size_t lo = static_cast<std::size_t>(b) * kSumBlock;
    const std::size_t hi = lo + kSumBlock < n ? lo + kSumBlock : n;
    double s = 0.0;
    for (std::size_t k = lo; k < hi; ++k) s += f(k);
    part[b] = s;
  }
  double total = 0.0;
  for (std::size_t b = 0; b < blocks; ++b) total += part[b];
  return total;
}

}  // namespace hexdem::solver
