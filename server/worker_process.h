// Jobs in worker processes: a mesh that crashes the engine, exhausts its memory or spins
// past its CPU time takes down one child process, never the server.
//
// Each worker thread keeps one child: the server's own binary re-executed as `spheremap
// worker-process` (worker_protocol.h says what they exchange), with the address space and
// CPU time limited by setrlimit and SIGKILL on the server's death (PR_SET_PDEATHSIG), so
// that no orphan keeps mapping. The child maps one job after another; the thread streams
// its progress and artifacts into the Job as they arrive, kills it within 100 ms of a
// cancel (dropping whatever it had sent), and turns a death by signal into the job's
// `worker_crashed` problem with the signal's name. A fresh child replaces one that
// crashed or was killed, and one that has served kJobsPerProcess jobs (memory
// fragmentation and the CPU-time limit grow with a process's age).
#pragma once

#include <sys/types.h>

#include <string>

#include "server/api_types.h"
#include "server/job_runner.h"

namespace spheremap::server {

struct WorkerLimits {
  std::string executable;     // the spheremap binary; "" = this process's own (/proc/self/exe)
  size_t memory_bytes = 0;    // RLIMIT_AS of the child; 0 = none
  double cpu_seconds = 0;     // RLIMIT_CPU of the child; 0 = none
  size_t max_artifact_bytes;  // a larger frame from the child is a bug: the job fails
  // The watchdog kills a child still busy this long past the job's time limit, or as long
  // again as the limit when that is longer (writing outputs is not time-limited).
  double min_overrun_seconds = 30;
};

// One worker process, kept for job after job by the worker thread that owns it: started
// at once (warm), restarted after a crash, a kill (cancel, time) or kJobsPerProcess jobs.
class WorkerProcess {
 public:
  static constexpr size_t kJobsPerProcess = 200;

  explicit WorkerProcess(WorkerLimits limits);
  ~WorkerProcess();  // closes the child's stdin: it exits between jobs
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  // Runs `job` in the child; same contract as run_job (never throws, returns the terminal
  // status, the job holds results or the error). A child that dies before it has read
  // the job (killed while idle, or one that could not start) is replaced and the job
  // given to the new one, once.
  JobStatus run(Job& job, const RunLimits& limits);
  pid_t pid() const { return pid_; }

 private:
  // One try; `began` is set once the child has read the job (it answered something).
  JobStatus run_once(Job& job, const RunLimits& limits, bool& began);
  bool start();
  int stop(bool kill_now);

  const WorkerLimits limits_;
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1;
  size_t jobs_ = 0;
};

// The child's side: reads the request on stdin, runs the job, answers on stdout.
// Returns the process exit code.
int worker_process_main();

}  // namespace spheremap::server
