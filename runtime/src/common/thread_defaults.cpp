#include "tensormass/common/thread_defaults.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace tensormass {

void apply_default_wait_policy(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", kDefaultWaitPolicy, 1) != 0) return;
  std::fflush(nullptr);
  execv("/proc/self/exe", argv);
  unsetenv("OMP_WAIT_POLICY");  // not re-executed: the environment says what this process runs with
}

}  // namespace tensormass
