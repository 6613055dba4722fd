#include "server/worker_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <fstream>
#include <mutex>
#include <new>
#include <sstream>
#include <thread>

#include "api/log.h"
#include "core/mesh/address_sanitizer.h"
#include "server/worker_protocol.h"

namespace spheremap::server {
namespace {

// Under AddressSanitizer a process reserves terabytes of shadow address space, so an
// RLIMIT_AS would stop the worker before it starts; sanitizer builds run without it.
constexpr bool kAddressSpaceLimitUsable = !kAddressSanitizer;

bool write_all(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n, size -= static_cast<size_t>(n);
  }
  return true;
}

void fail_job(Job& job, int status, const char* problem, const char* title, std::string detail) {
  std::lock_guard lock(job.mutex);
  job.artifacts.clear();  // a partial answer is never served
  job.metrics = nullptr;
  job.error = JobError{status, problem, title, std::move(detail)};
}

struct Child {
  pid_t pid = -1;
  int in = -1, out = -1;  // the child's stdin (we write), its stdout (we read)
};

// Everything the child needs is prepared before fork(): after it, only async-signal-safe
// calls until execv.
Child spawn(const WorkerLimits& worker) {
  int to_child[2], from_child[2];
  if (pipe2(to_child, O_CLOEXEC) != 0) return {};
  if (pipe2(from_child, O_CLOEXEC) != 0) {
    close(to_child[0]), close(to_child[1]);
    return {};
  }
  const std::string executable = worker.executable.empty() ? "/proc/self/exe" : worker.executable;
  const char* argv[] = {executable.c_str(), "worker-process", nullptr};
  rlimit memory{static_cast<rlim_t>(worker.memory_bytes), static_cast<rlim_t>(worker.memory_bytes)};
  const rlim_t cpu = static_cast<rlim_t>(std::ceil(worker.cpu_seconds));
  rlimit cpu_limit{cpu, cpu + 5};  // SIGXCPU at the soft limit, SIGKILL 5 s later
  const pid_t server = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != server) _exit(126);  // the server died between fork and prctl
    dup2(to_child[0], STDIN_FILENO);
    dup2(from_child[1], STDOUT_FILENO);
    if (worker.memory_bytes > 0 && kAddressSpaceLimitUsable) setrlimit(RLIMIT_AS, &memory);
    if (cpu > 0) setrlimit(RLIMIT_CPU, &cpu_limit);
    execv(argv[0], const_cast<char* const*>(argv));
    _exit(127);
  }
  close(to_child[0]), close(from_child[1]);
  if (pid < 0) {
    close(to_child[1]), close(from_child[0]);
    return {};
  }
  return {pid, to_child[1], from_child[0]};
}

// 10 -> "10", 2.5 -> "2.5".
std::string seconds_text(double seconds) {
  std::ostringstream text;
  text << seconds;
  return text.str();
}

std::string signal_text(int signal) {
  const char* name = sigabbrev_np(signal);
  return std::string("SIG") + (name ? name : std::to_string(signal)) + " (" + strsignal(signal) +
         ")";
}

// CPU time (user + system) a running process has used, from /proc/PID/stat.
double cpu_seconds_of(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  const size_t close = line.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return 0;
  std::istringstream fields(line.substr(close + 2));
  std::string field;
  unsigned long long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) utime = std::stoull(field);
    if (i == 15) stime = std::stoull(field);
  }
  return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

// Applies one frame from the child to the job; returns the status once the child sent it.
std::optional<JobStatus> apply(Job& job, const FrameReader::Frame& frame) {
  std::lock_guard lock(job.mutex);
  switch (frame.type) {
    case FrameType::kProgress:
      job.progress = progress_from_json(frame.payload);
      break;
    case FrameType::kArtifact: {
      const size_t newline = frame.payload.find('\n');
      const nlohmann::json header = nlohmann::json::parse(frame.payload.substr(0, newline));
      job.artifacts.push_back(make_artifact(header.at("name"), header.at("content_type"),
                                            frame.payload.substr(newline + 1)));
      break;
    }
    case FrameType::kMetrics:
      job.metrics = nlohmann::json::parse(frame.payload);
      break;
    case FrameType::kError:
      job.error = error_from_json(frame.payload);
      break;
    case FrameType::kStatus: {
      const std::string status = nlohmann::json::parse(frame.payload).at("status");
      if (status == "succeeded") return JobStatus::kSucceeded;
      if (status == "cancelled") return JobStatus::kCancelled;
      return JobStatus::kFailed;
    }
  }
  return std::nullopt;
}

}  // namespace

WorkerProcess::WorkerProcess(WorkerLimits limits) : limits_(std::move(limits)) {
  start();  // warm: the first job does not pay for the start
}

WorkerProcess::~WorkerProcess() {
  stop(false);
}

bool WorkerProcess::start() {
  if (pid_ > 0) return true;
  const Child child = spawn(limits_);
  if (child.pid < 0) return false;
  pid_ = child.pid, in_ = child.in, out_ = child.out;
  jobs_ = 0;
  return true;
}

// Ends the child: at once (SIGKILL), or by closing its stdin (it exits between jobs).
// Returns its wait status.
int WorkerProcess::stop(bool kill_now) {
  if (pid_ <= 0) return 0;
  if (kill_now) kill(pid_, SIGKILL);
  if (in_ >= 0) close(in_);
  if (out_ >= 0) close(out_);
  int wait_status = 0;
  while (waitpid(pid_, &wait_status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1, in_ = out_ = -1;
  return wait_status;
}

JobStatus WorkerProcess::run(Job& job, const RunLimits& limits) {
  // A child that died before it read the job (killed while idle, or a replacement that
  // could not start) never ran it: that is no verdict on the job, so it gets one more try
  // on a fresh child. A job that began is not run again (it may be what crashed).
  bool began = false;
  const JobStatus status = run_once(job, limits, began);
  if (began || status != JobStatus::kFailed || job.cancel) return status;
  std::string first_error;
  {
    std::lock_guard lock(job.mutex);
    if (job.error) first_error = job.error->detail;
    job.error.reset();
    job.progress.stage = "starting";
  }
  api::log_event({{"event", "worker_retry"},
                  {"job", job.id},
                  {"reason", "the worker process died before it began the job"},
                  {"error", first_error}});
  return run_once(job, limits, began);
}

JobStatus WorkerProcess::run_once(Job& job, const RunLimits& limits, bool& began) {
  began = false;
  std::string request;
  double time_limit = limits.time_limit_seconds;
  {
    std::lock_guard lock(job.mutex);
    if (job.spec->map.time_limit_seconds > 0)
      time_limit = std::min(time_limit, job.spec->map.time_limit_seconds);
    try {
      request = encode_request(*job.spec, limits.time_limit_seconds, limits.threads);
    } catch (const std::bad_alloc&) {
      request = std::string();
      job.artifacts.clear();
      job.metrics = nullptr;
      job.error = JobError{507, "out_of_memory", "Out of memory",
                           "the server ran out of memory writing this job's request to its "
                           "worker; the job failed, the server and the other jobs are "
                           "unaffected; try a smaller mesh"};
      return JobStatus::kFailed;
    }
  }
  if (!start()) {
    fail_job(job, 503, "worker_unavailable", "No worker process",
             std::string("could not start a worker process: ") + std::strerror(errno));
    return JobStatus::kFailed;
  }
  ++jobs_;
  // Whatever throws from here on (std::bad_alloc buffering an answer) leaves no child
  // behind with half an answer in its pipe: it is killed, the next job gets a fresh one.
  struct KillOnThrow {
    WorkerProcess& process;
    int pending = std::uncaught_exceptions();
    ~KillOnThrow() {
      if (std::uncaught_exceptions() > pending) process.stop(true);
    }
  } kill_on_throw{*this};
  // Length first, then the request. The child reads all of it before it writes anything,
  // so the two never wait on each other. A child that has died makes the write fail
  // (EPIPE; SIGPIPE is ignored by the service) and the read below sees it.
  const uint64_t length = request.size();
  const bool sent = write_all(in_, reinterpret_cast<const char*>(&length), sizeof length) &&
                    write_all(in_, request.data(), request.size());
  request = std::string();

  // The engine stops itself at the time limit; the output stages after it are not
  // limited, so the watchdog allows as long again (at least 30 s) before it kills.
  const double grace = std::max(limits_.min_overrun_seconds, time_limit);
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(time_limit + grace));
  FrameReader frames;
  std::optional<JobStatus> status;
  bool killed_for_cancel = false, killed_for_time = false, protocol_error = false;
  std::vector<char> chunk(1 << 16);
  while (sent && !status) {
    pollfd p{out_, POLLIN, 0};
    const int ready = poll(&p, 1, 100);
    if (ready < 0 && errno != EINTR) break;
    if (job.cancel && !killed_for_cancel) {
      kill(pid_, SIGKILL);
      killed_for_cancel = true;
    }
    if (Clock::now() > deadline && !killed_for_time && !killed_for_cancel) {
      kill(pid_, SIGKILL);
      killed_for_time = true;
    }
    if (ready <= 0) continue;
    const ssize_t n = read(out_, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // the child is gone
    began = true;       // it answers only once it has read the whole request
    frames.append(chunk.data(), static_cast<size_t>(n));
    try {
      while (auto frame = frames.next(limits_.max_artifact_bytes))
        if (auto s = apply(job, *frame)) status = s;
    } catch (const std::exception&) {
      protocol_error = true;
      kill(pid_, SIGKILL);
      break;
    }
  }
  // A child that answered stays for the next job, unless it has served its share (memory
  // fragmentation and the CPU-time limit both grow with a process's age).
  if (status && !killed_for_cancel && !killed_for_time && !protocol_error) {
    if (jobs_ >= kJobsPerProcess ||
        (limits_.cpu_seconds > 0 && cpu_seconds_of(pid_) > limits_.cpu_seconds / 2))
      stop(false);  // the next job gets a fresh process and its whole CPU-time limit
    return *status;
  }
  const int wait_status = stop(true);

  if (killed_for_cancel || job.cancel) {
    std::lock_guard lock(job.mutex);
    job.artifacts.clear();  // cancel deletes what the job made
    return JobStatus::kCancelled;
  }
  if (killed_for_time) {
    began = true;  // whatever it was doing, it had the job for that long
    fail_job(job, 422, "time_limit", "Time limit reached",
             "the worker was still busy " + seconds_text(grace) + " s past the time limit of " +
                 seconds_text(time_limit) + " s and was stopped");
    return JobStatus::kFailed;
  }
  if (protocol_error) {
    began = true;
    fail_job(job, 500, "internal", "Internal error", "the worker process sent a malformed answer");
    return JobStatus::kFailed;
  }
  if (WIFSIGNALED(wait_status) && WTERMSIG(wait_status) != SIGKILL) {
    const int signal = WTERMSIG(wait_status);
    fail_job(job, 500, "worker_crashed", "Worker crashed",
             "the worker process mapping this job was killed by " + signal_text(signal) +
                 (signal == SIGXCPU ? " (over its CPU-time limit, worker_cpu_seconds)" : "") +
                 "; the server and the other jobs are unaffected");
    return JobStatus::kFailed;
  }
  fail_job(job, 500, "worker_crashed", "Worker crashed",
           "the worker process mapping this job " +
               std::string(WIFSIGNALED(wait_status)
                               ? "was killed by SIGKILL (Killed) (by the kernel's out-of-memory "
                                 "killer, an operator, or over its CPU-time limit)"
                               : "exited with code " + std::to_string(WEXITSTATUS(wait_status)) +
                                     " before it answered" +
                                     (WEXITSTATUS(wait_status) == 127
                                          ? " (the worker executable could not be started)"
                                          : "")) +
               "; the server and the other jobs are unaffected");
  return JobStatus::kFailed;
}

namespace {

bool read_exactly(int fd, char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::read(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n, size -= static_cast<size_t>(n);
  }
  return true;
}

// One job in the child: decode, run with progress every 100 ms (woken at the end so a
// short job does not wait out the interval), answer.
void serve_one(const std::string& request) {
  std::mutex out_mutex;
  auto send = [&](FrameType type, const std::string& payload) {
    const std::string frame = encode_frame(type, payload);
    std::lock_guard lock(out_mutex);
    write_all(STDOUT_FILENO, frame.data(), frame.size());
  };
  Job job;
  RunLimits limits;
  try {
    WorkerRequest decoded = decode_request(request);
    limits.time_limit_seconds = decoded.time_limit_seconds;
    limits.threads = decoded.threads;
    job.spec = std::make_unique<JobSpec>(std::move(decoded.spec));
  } catch (const std::bad_alloc&) {
    // The request alone did not fit in the worker's address space (worker_memory_bytes).
    send(FrameType::kError, error_json({507, "out_of_memory", "Out of memory",
                                        "the job's input does not fit in the worker's memory "
                                        "limit; try a smaller mesh"}));
    send(FrameType::kStatus, R"({"status":"failed"})");
    return;
  } catch (const std::exception& e) {
    send(FrameType::kError, error_json({500, "internal", "Internal error", e.what()}));
    send(FrameType::kStatus, R"({"status":"failed"})");
    return;
  }
  std::mutex stop_mutex;
  std::condition_variable stop_cv;
  bool stopping = false;
  std::thread reporter([&] {
    std::string last;
    std::unique_lock stop_lock(stop_mutex);
    while (!stop_cv.wait_for(stop_lock, std::chrono::milliseconds(100), [&] { return stopping; })) {
      std::string now;
      {
        std::lock_guard lock(job.mutex);
        now = progress_json(job.progress);
      }
      if (now != last) send(FrameType::kProgress, last = now);
    }
  });
  const JobStatus status = run_job(job, limits);
  {
    std::lock_guard stop_lock(stop_mutex);
    stopping = true;
  }
  stop_cv.notify_one();
  reporter.join();
  std::lock_guard lock(job.mutex);
  send(FrameType::kProgress, progress_json(job.progress));
  for (const Artifact& a : job.artifacts)
    send(FrameType::kArtifact,
         nlohmann::json{{"name", a.name}, {"content_type", a.content_type}}.dump() + "\n" +
             *a.bytes);
  if (!job.metrics.is_null()) send(FrameType::kMetrics, job.metrics.dump());
  if (job.error) send(FrameType::kError, error_json(*job.error));
  send(FrameType::kStatus, nlohmann::json{{"status", to_string(status)}}.dump());
}

}  // namespace

int worker_process_main() {
  // Requests until the server closes our stdin: each a uint64 length and the request.
  for (;;) {
    uint64_t length = 0;
    if (!read_exactly(STDIN_FILENO, reinterpret_cast<char*>(&length), sizeof length)) return 0;
    if (length > (uint64_t{1} << 40)) return 2;  // not our server
    std::string request(static_cast<size_t>(length), '\0');
    if (!read_exactly(STDIN_FILENO, request.data(), request.size())) return 0;
    // The first frame says the job has begun: a child that dies before it was not given
    // the job, and the server tries it again elsewhere (WorkerProcess::run).
    const std::string begun = encode_frame(FrameType::kProgress, R"({"stage":"starting"})");
    write_all(STDOUT_FILENO, begun.data(), begun.size());
    serve_one(request);
  }
}

}  // namespace spheremap::server
