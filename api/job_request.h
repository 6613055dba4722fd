// A job submission (POST /v1/jobs, POST /v1/map) read into a JobSpec: the content type,
// the mesh (GLB, glTF JSON, OBJ, OFF, STL or PLY, as the body or a multipart `mesh` part;
// see upload_format.h for how its format is told), the options, the server's caps,
// and the topology checks, so that every accepted job can be mapped. Errors are Problems:
// 400 malformed, 413 too large, 415 wrong type, 422 not a closed genus-0 manifold.
#pragma once

#include <httplib.h>

#include <memory>

#include "api/backend.h"
#include "api/intake.h"
#include "api/job.h"

namespace spheremap::api {

// The 415 detail for a mesh sent as a form (curl's default for --data-binary).
extern const char* const kFormEncodedHint;

// Checks `deadline` between its stages (options, mesh read, weld and topology).
std::unique_ptr<JobSpec> read_job_request(const httplib::Request& request,
                                          const ApiSettings& config,
                                          const IntakeDeadline& deadline);

}  // namespace spheremap::api
