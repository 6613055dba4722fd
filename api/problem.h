// Errors as application/problem+json (RFC 9457): a type URI per kind of problem, a
// title, the status, and a detail that names the failed check with its counts.
#pragma once

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace spheremap::api {

// Problem type URIs are "/v1/problems/<slug>" on the service, documented in openapi.yaml.
struct Problem : std::runtime_error {
  Problem(int status, std::string slug, std::string title, const std::string& detail,
          nlohmann::json extra = nlohmann::json::object())
      : std::runtime_error(detail),
        status(status),
        slug(std::move(slug)),
        title(std::move(title)),
        extra(std::move(extra)) {}
  int status;
  std::string slug, title;
  nlohmann::json extra;  // more members: "check", "failures", ...
};

nlohmann::json problem_json(const Problem& problem, const std::string& instance = "");

// Sets the status, the body and the content type of `response`.
void send_problem(httplib::Response& response, const Problem& problem,
                  const std::string& instance = "");

}  // namespace spheremap::api
