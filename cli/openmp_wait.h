// The OpenMP wait policy the program runs with.
#pragma once

namespace spheremap::cli {

// When neither OMP_WAIT_POLICY nor GOMP_SPINCOUNT is set: sets OMP_WAIT_POLICY=passive and
// runs the program again with the same arguments (libgomp reads the policy once, as it
// loads). Returns only when nothing was to be done or the new run could not start (then
// this run goes on with libgomp's default policy).
//
// Why: libgomp's threads spin (about 300,000 rounds) at every barrier before they sleep.
// The optimizer has a barrier per colour class per sweep (hundreds per map), and on a
// machine shared with other work the spinning thread takes the core from the thread it
// waits for. Measured (session 33, 2 cores at load 5, default threads): horse `fast`
// 2.94 -> 0.90 s wall, 1.84 -> 0.77 s of CPU; scorpion `standard` 7.87 -> 2.75 s. The
// map is bit-identical for any thread count and wait policy.
void prefer_passive_openmp_wait(char** argv);

}  // namespace spheremap::cli
