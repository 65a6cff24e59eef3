#pragma once
/// \file solver_text.hpp
/// Number formatting for the solver's messages (internal to the solver library).
#include <sstream>
#include <string>

namespace hexdem::solver::detail {

/// v with `precision` significant digits, as the messages print it.
inline std::string fmt(double v, int precision = 4) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace hexdem::solver::detail
