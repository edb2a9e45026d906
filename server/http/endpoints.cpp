#include "http/endpoints.hpp"

#include <regex>
#include <utility>

namespace compaction::server {

namespace {

const std::vector<std::pair<const Endpoint*, std::regex>>& table() {
  using namespace endpoints;
  static const auto t = [] {
    std::vector<std::pair<const Endpoint*, std::regex>> out;
    for (const Endpoint* e :
         {&create_sweep, &list_sweeps, &show_sweep, &cancel_sweep, &export_sweep, &estimate_sweep,
          &sweep_plan, &list_jobs, &show_job, &list_artifacts, &artifact, &phase_map,
          &phase_regions, &lease, &heartbeat, &complete, &fail, &release, &put_checkpoint,
          &get_checkpoint, &health, &metrics, &api_metrics, &openapi, &presets, &limits,
          &set_label, &clear_label, &show_label, &label_audit, &import_sweep}) {
      out.emplace_back(e, std::regex(e->pattern));
    }
    return out;
  }();
  return t;
}

}  // namespace

const Endpoint& find_endpoint(const std::string& method, const std::string& path) {
  const std::string m = method == "HEAD" ? "GET" : method;
  for (const auto& [e, re] : table()) {
    if (m == e->method && std::regex_match(path, re)) return *e;
  }
  return other_request;
}

void add_route(httplib::Server& server, const Endpoint& e, Handler handler) {
  const std::string method = e.method;
  if (method == "GET") {
    server.Get(e.pattern, guarded(std::move(handler)));
  } else if (method == "PUT") {
    server.Put(e.pattern, guarded(std::move(handler)));
  } else if (method == "DELETE") {
    server.Delete(e.pattern, guarded(std::move(handler)));
  } else {
    server.Post(e.pattern, guarded(std::move(handler)));
  }
}

void add_streaming_route(httplib::Server& server, const Endpoint& e, StreamingHandler handler) {
  auto wrapped = [handler = std::move(handler)](const httplib::Request& req, httplib::Response& res,
                                                const httplib::ContentReader& reader) {
    guarded([&](const httplib::Request& r, httplib::Response& s) { handler(r, s, reader); })(req, res);
  };
  if (std::string(e.method) == "PUT") {
    server.Put(e.pattern, std::move(wrapped));
  } else {
    server.Post(e.pattern, std::move(wrapped));
  }
}

}  // namespace compaction::server
