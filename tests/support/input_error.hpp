// The message of the InputError an action throws, for tests of error text.
#ifndef TENSORMASS_TEST_SUPPORT_INPUT_ERROR_HPP
#define TENSORMASS_TEST_SUPPORT_INPUT_ERROR_HPP

#include <string>

#include "tensormass/common/errors.hpp"

namespace test_support {

/// The message of the InputError `action` throws ("" when it throws none).
template <class Action>
std::string input_error(Action action) {
  try {
    action();
  } catch (const tensormass::InputError& error) {
    return error.what();
  }
  return "";
}

}  // namespace test_support

#endif
