#include "tensormass/common/thread_defaults.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace tensormass {

void apply_default_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  const bool spin_set = std::getenv("GOMP_SPINCOUNT") != nullptr;
  if (setenv("OMP_WAIT_POLICY", kDefaultWaitPolicy, 1) != 0) return;
  if (!spin_set && setenv("GOMP_SPINCOUNT", kDefaultSpinCount, 1) != 0) {
    unsetenv("OMP_WAIT_POLICY");
    return;
  }
  std::fflush(nullptr);
  execv("/proc/self/exe", argv);
  // Not re-executed: the environment says what this process runs with.
  unsetenv("OMP_WAIT_POLICY");
  if (!spin_set) unsetenv("GOMP_SPINCOUNT");
}

}  // namespace tensormass
