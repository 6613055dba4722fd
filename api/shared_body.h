// A response body that is shared bytes (an artifact, a .gltf view), sent without copying
// them: the response holds a reference until it is written, so any number of parallel
// downloads of one artifact cost its size once.
#pragma once

#include <httplib.h>

#include <string>

#include "api/job.h"

namespace spheremap::api {

// Sets `bytes` (not null) as the body of `response`, of `content_type`. cpp-httplib
// writes it in chunks (and applies a Range to it like to any body).
void send_shared(httplib::Response& response, SharedBytes bytes, const std::string& content_type);

}  // namespace spheremap::api
