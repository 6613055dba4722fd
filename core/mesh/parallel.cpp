#include "core/mesh/parallel.h"

#include <omp.h>

namespace spheremap {

int resolve_threads(int threads) {
  return threads > 0 ? threads : omp_get_num_procs();
}

}  // namespace spheremap
