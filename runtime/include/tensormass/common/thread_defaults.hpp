/// \file thread_defaults.hpp
/// The OpenMP settings tensormass programs start with. Idle OpenMP threads
/// spin by default for about 3 ms (libgomp: OMP_WAIT_POLICY unset), which
/// takes a core from the serial phases (sparse Cholesky, a busy second core)
/// and made 2 threads slower than one. Passive waiting (sleep at once)
/// fixed that, but each parallel region then wakes its threads through the
/// kernel: on an explicit step of a fraction of a millisecond that cost 20
/// to 30 %. So idle threads spin briefly (GOMP_SPINCOUNT, about 0.1 ms),
/// then sleep. libgomp reads both from the environment once, when it is
/// loaded, so a program sets them by starting again with them.
#ifndef TENSORMASS_COMMON_THREAD_DEFAULTS_HPP
#define TENSORMASS_COMMON_THREAD_DEFAULTS_HPP

namespace tensormass {

/// The wait policy tensormass programs use when the user has not set OMP_WAIT_POLICY.
inline constexpr const char* kDefaultWaitPolicy = "passive";
/// The spins before an idle thread sleeps (libgomp's GOMP_SPINCOUNT, which it
/// estimates at 100,000 a millisecond), set with kDefaultWaitPolicy unless
/// the user set GOMP_SPINCOUNT.
inline constexpr const char* kDefaultSpinCount = "10000";

/// Call first in main(): when OMP_WAIT_POLICY is unset, sets it to
/// kDefaultWaitPolicy (and GOMP_SPINCOUNT, when unset, to kDefaultSpinCount)
/// and re-executes the program (/proc/self/exe) with the same arguments;
/// returns only when the policy was already set or the re-execution failed
/// (then the run goes on with libgomp's defaults).
void apply_default_wait_policy(char** argv);

}  // namespace tensormass

#endif
