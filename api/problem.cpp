#include "api/problem.h"

namespace spheremap::api {

nlohmann::json problem_json(const Problem& problem, const std::string& instance) {
  nlohmann::json body = {{"type", "/v1/problems/" + problem.slug},
                         {"title", problem.title},
                         {"status", problem.status},
                         {"detail", problem.what()}};
  if (!instance.empty()) body["instance"] = instance;
  for (const auto& [key, value] : problem.extra.items()) body[key] = value;
  return body;
}

void send_problem(httplib::Response& response, const Problem& problem,
                  const std::string& instance) {
  response.status = problem.status;
  // Details can quote a client's bytes: invalid UTF-8 is replaced, never thrown.
  const auto replace = nlohmann::json::error_handler_t::replace;
  response.set_content(problem_json(problem, instance).dump(2, ' ', false, replace) + "\n",
                       "application/problem+json");
}

}  // namespace spheremap::api
