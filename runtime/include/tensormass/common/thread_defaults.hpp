/// \file thread_defaults.hpp
/// The OpenMP settings tensormass programs start with. Idle OpenMP threads
/// spin by default (libgomp: OMP_WAIT_POLICY unset), which takes a core
/// from the serial phases (sparse Cholesky, a busy second core) and made 2
/// threads slower than one; passive waiting measured as fast or faster in
/// every case (README "Performance"). libgomp reads the policy from the
/// environment once, when it is loaded, so a program sets it by starting
/// again with it.
#ifndef TENSORMASS_COMMON_THREAD_DEFAULTS_HPP
#define TENSORMASS_COMMON_THREAD_DEFAULTS_HPP

namespace tensormass {

/// The wait policy tensormass programs use when the user has not set OMP_WAIT_POLICY.
inline constexpr const char* kDefaultWaitPolicy = "passive";

/// Call first in main(): when OMP_WAIT_POLICY is unset, sets it to
/// kDefaultWaitPolicy and re-executes the program (/proc/self/exe) with the
/// same arguments; returns only when the policy was already set or the
/// re-execution failed (then the run goes on with libgomp's default).
void apply_default_wait_policy(char** argv);

}  // namespace tensormass

#endif
