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

}  // namespace tensormass

#endif
