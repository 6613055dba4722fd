// Jobs in worker processes: a mesh that crashes the engine, exhausts its memory or spins
// past its CPU time takes down one child process, never the server.
//
// For each job the supervising worker thread forks and re-executes the server's own
// binary as `spheremap worker-process` (worker_protocol.h says what they exchange), with
// the address space and CPU time limited by setrlimit and SIGKILL on the server's death
// (PR_SET_PDEATHSIG), so that no orphan keeps mapping. The thread streams the child's
// progress and artifacts into the Job as they arrive, kills the child within 100 ms of a
// cancel (dropping whatever it had sent), and turns a death by signal into the job's
// `worker_crashed` problem with the signal's name. A new child is started for the next
// job, so one that crashed leaves nothing behind.
#pragma once

#include <string>

#include "server/job.h"
#include "server/job_runner.h"

namespace spheremap::server {

struct WorkerLimits {
  std::string executable;     // the spheremap binary; "" = this process's own (/proc/self/exe)
  size_t memory_bytes = 0;    // RLIMIT_AS of the child; 0 = none
  double cpu_seconds = 0;     // RLIMIT_CPU of the child; 0 = none
  size_t max_artifact_bytes;  // a larger frame from the child is a bug: the job fails
};

// Runs `job` in a child process; same contract as run_job (never throws, returns the
// terminal status, the job holds results or the error).
JobStatus run_job_in_worker(Job& job, const RunLimits& limits, const WorkerLimits& worker);

// The child's side: reads the request on stdin, runs the job, answers on stdout.
// Returns the process exit code.
int worker_process_main();

}  // namespace spheremap::server
