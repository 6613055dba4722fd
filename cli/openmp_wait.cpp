#include "cli/openmp_wait.h"

#include <unistd.h>

#include <cstdlib>

namespace spheremap::cli {

void prefer_passive_openmp_wait(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
  execv("/proc/self/exe", argv);  // returns only when it failed (no /proc)
}

}  // namespace spheremap::cli
