/// \file errors.hpp
/// The two failure kinds the command line maps to exit codes:
/// InputError (bad file, key or value: exit 2, nothing written) and
/// NumericalError (divergence, inversion, NaN: exit 3, last good state kept).
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

/// A matrix a direct solver needed positive definite was not (an
/// indefinite tangent, or a singular one: an unconstrained body). Static
/// Newton answers it with a shifted step (static_solver.cpp).
class NotPositiveDefiniteError : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

}  // namespace tensormass

#endif
