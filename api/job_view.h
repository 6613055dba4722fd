// The JSON a client sees of a job (GET /v1/jobs/{id}, the 202 of a submission).
#pragma once

#include <nlohmann/json.hpp>

#include "api/job.h"

namespace spheremap::api {

// `queue_position` from JobStore::queue_position (0 when not queued).
nlohmann::json job_json(const Job& job, size_t queue_position);

std::string job_path(const std::string& id);  // "/v1/jobs/<id>"

}  // namespace spheremap::api
