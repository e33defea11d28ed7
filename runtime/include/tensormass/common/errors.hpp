/// \file errors.hpp
/// The failure kinds the command line maps to exit codes: InputError (bad
/// file, key or value: exit 2, nothing written), NumericalError
/// (divergence, inversion, NaN: exit 3, last good state kept) and
/// OutputError (a write failed during a run: exit 4, the files written
/// before it stay whole).
#ifndef TENSORMASS_ERRORS_HPP
#define TENSORMASS_ERRORS_HPP

#include <stdexcept>
#include <string>

namespace tensormass {

/// Bad input. The message names the file and line, element, key or parameter.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure during a solve. The message says what failed where.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be written while running (disk full, an I/O error): no
/// half-written file is left. The message names the file and the reason.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A matrix a direct solver needed positive definite was not (an
/// indefinite tangent, or a singular one: an unconstrained body). Static
/// Newton answers it with a shifted step (static_solver.cpp).
class NotPositiveDefiniteError : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

}  // namespace tensormass

#endif
