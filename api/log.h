// Structured logs: one JSON object per line on stderr, with a UTC timestamp.
#pragma once

#include <nlohmann/json.hpp>

namespace spheremap::api {

// Writes {"time": ..., fields...} as one line; safe from any thread.
void log_event(nlohmann::json fields);

// Seconds between two steady-clock points, rounded to milliseconds, for logs.
double rounded_seconds(double seconds);

}  // namespace spheremap::api
