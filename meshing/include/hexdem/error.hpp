#pragma once
/// \file error.hpp
/// Errors that reach users, and always-on / debug-only invariant checks.
///
/// Input errors are thrown at set-up as hexdem::InputError with a one-line message that names
/// the file, the key or line, and the offending value. `main` catches them, prints the line to
/// stderr and exits with code 2 (see apps/hexdem_main.cpp). Kernels never throw.

#include <stdexcept>
#include <string>

namespace hexdem {

/// Bad user input (file, key or line, value). Exit code 2.
class InputError : public std::runtime_error {
public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

/// Exit codes of the `hexdem` program.
enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,     ///< internal error: a bug (a broken invariant, an unexpected exception)
  kExitInputError = 2,  ///< bad input (InputError)
  /// The run reached its end time, but a run-health warning fired on the way (its energy
  /// balance passed `[time] energy_warning`): the series is complete and its numbers may be
  /// wrong. `<case>.status` says `completed with warning: ...`.
  kExitWarning = 3,
  /// The run stopped before its end: a numerical blow-up or an energy balance failure (above
  /// `[time] energy_limit`). The last good frame is kept and named, `<case>.status` says
  /// `failed: ...`. `hexdem sweep` exits with it when a member did not run to its end.
  kExitRunFailed = 4,
};

}  // namespace hexdem

/// Always-on invariant check; throws std::logic_error with the location.
#define HEXDEM_VERIFY(cond, msg)                                                           \
  do {                                                                                     \
    if (!(cond))                                                                           \
      throw std::logic_error(std::string(__FILE__) + ":" + std::to_string(__LINE__) +      \
                             ": check failed: " #cond ": " + std::string(msg));            \
  } while (0)

#ifdef NDEBUG
#define HEXDEM_ASSERT(cond, msg) ((void)0)
#else
/// Debug-only invariant check (compiled out in release builds).
#define HEXDEM_ASSERT(cond, msg) HEXDEM_VERIFY(cond, msg)
#endif
