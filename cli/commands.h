// The subcommands of the spheremap tool. Each returns the process exit code.
#pragma once

#include <stdexcept>

namespace spheremap::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 1;
inline constexpr int kExitInvalidInput = 2;
inline constexpr int kExitNotBijective = 3;
// An output file could not be written (and any error that is not the input's).
inline constexpr int kExitOutputError = 4;

// The time limit passed before there was any map to write (exit 3, "time_limit").
struct TimeLimitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

int run_map(int argc, char** argv);
int run_info(int argc, char** argv);
int run_serve(int argc, char** argv);
int run_worker(int argc, char** argv);
int run_remesh(int argc, char** argv);
int run_uv(int argc, char** argv);
int run_morph(int argc, char** argv);
int run_health(int argc, char** argv);

}  // namespace spheremap::cli
