#include "scheduler/http/dashboard_api.h"

#include <httplib.h>

#include <charconv>
#include <stdexcept>

#include "scheduler/http/dashboard_assets.h"
#include "scheduler/http/dashboard_json.h"
#include "scheduler/farm_names.h"
#include "scheduler/quoted_text.h"
#include "scheduler/shot_report.h"

namespace pathfarm::farm {
namespace {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

constexpr const char* kJson = "application/json";
constexpr int64_t kDefaultTaskPage = 200, kLargestTaskPage = 2000;

// A request the API cannot read (a path part that is no number, a body that is no JSON).
class BadRequest : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

int64_t integerFrom(const std::string& text, const std::string& what) {
  int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || text.empty())
    throw BadRequest(what + " must be a whole number, not " + quotedInput(text));
  return value;
}

int64_t idFrom(const std::string& text, const std::string& what) {
  const int64_t id = integerFrom(text, what);
  if (id < 0) throw BadRequest(what + " must not be negative");
  return id;
}

int64_t shotIdOf(const Request& request) { return idFrom(request.matches[1], "the shot id"); }

void sendJson(Response& response, const json& body) {
  response.set_header("Cache-Control", "no-store");
  response.set_content(body.dump(), kJson);
}

void sendError(Response& response, int status, const std::string& message) {
  response.status = status;
  sendJson(response, {{"error", message}});
}

// Runs a handler; what its exception means becomes the status: a request it cannot read
// 400, an unknown shot 404, a request the farm refuses (requeueing a cancelled shot) 409.
template <class Handler>
httplib::Server::Handler guarded(Handler handler) {
  return [handler](const Request& request, Response& response) {
    try {
      handler(request, response);
    } catch (const BadRequest& e) {
      sendError(response, 400, e.what());
    } catch (const std::out_of_range& e) {
      sendError(response, 404, e.what());
    } catch (const std::invalid_argument& e) {
      sendError(response, 409, e.what());
    } catch (const std::exception& e) {
      sendError(response, 500, e.what());
    }
  };
}

// An action changes the farm: a JSON POST only. A web page of another origin cannot send
// one without the browser asking first (a CORS preflight this server never grants), so a
// farm without a token is not open to every site its user visits.
template <class Action>
httplib::Server::Handler action(DashboardContext c, Action act) {
  return guarded([c, act](const Request& request, Response& response) {
    if (request.get_header_value("Content-Type").rfind(kJson, 0) != 0)
      return sendError(response, 415, "an action is a POST with Content-Type: application/json");
    json body = json::object();
    if (!request.body.empty()) {
      body = json::parse(request.body, nullptr, false);
      if (body.is_discarded() || !body.is_object()) throw BadRequest("the body is not a JSON object");
    }
    sendJson(response, act(request, body));
    c.signal.notify();
  });
}

json summaryReply(const ShotSummary& summary) { return {{"summary", shotJson(summary)}}; }

void serveAssets(httplib::Server& server) {
  for (const DashboardAsset& asset : dashboardAssets()) {
    const auto send = [&asset](const Request&, Response& response) {
      response.set_header("Cache-Control", "no-cache");
      response.set_content(std::string(asset.bytes), std::string(contentTypeOf(asset.path)));
    };
    server.Get(std::string(asset.path), send);
    if (asset.path == "/index.html") server.Get("/", send);
  }
}

void serveReads(httplib::Server& server, DashboardContext c) {
  server.Get("/api/shots", guarded([c](const Request&, Response& response) {
               const double now = farmClockSeconds();
               json shots = json::array();
               for (const ShotSummary& s : c.state.shots(now)) shots.push_back(shotJson(s));
               sendJson(response, {{"shots", shots}, {"time", now}});
             }));
  server.Get(R"(/api/shots/([^/]+))", guarded([c](const Request& request, Response& response) {
               const int64_t id = shotIdOf(request);
               const ShotReply shot = c.state.shot(id, farmClockSeconds());
               sendJson(response, shotPageJson(shot, c.state.outputs(id), c.state.blocklist(id)));
             }));
  server.Get(R"(/api/shots/([^/]+)/tasks)", guarded([c](const Request& request, Response& response) {
               const int64_t id = shotIdOf(request);
               std::optional<int> state;
               if (request.has_param("state")) {
                 state = taskStateByName(request.get_param_value("state"));
                 if (!state) throw BadRequest("state is one of waiting, ready, leased, done, failed");
               }
               const int64_t offset = request.has_param("offset") ? idFrom(request.get_param_value("offset"), "offset") : 0;
               const int64_t limit = request.has_param("limit") ? idFrom(request.get_param_value("limit"), "limit")
                                                                : kDefaultTaskPage;
               if (limit > kLargestTaskPage) throw BadRequest("limit is at most " + std::to_string(kLargestTaskPage));
               const double now = farmClockSeconds();
               const ShotReply shot = c.state.shot(id, now);  // its events are the tasks' log
               const FarmState::TaskPage page = c.state.taskDetails(id, state, offset, limit);
               const std::vector<ShotEvent> events(shot.events().begin(), shot.events().end());
               sendJson(response, tasksJson(page, events, now));
             }));
  server.Get(R"(/api/shots/([^/]+)/report)", guarded([c](const Request& request, Response& response) {
               const int64_t id = shotIdOf(request);
               const ShotSummary summary = c.state.summary(id, farmClockSeconds());
               const auto [spec, tasks] = c.state.taskRecords(id);
               response.set_header("Cache-Control", "no-store");
               response.set_content(reportJson(buildReport(summary, spec, tasks)), kJson);
             }));
  server.Get(R"(/api/shots/([^/]+)/frames/([^/]+)/thumbnail\.png)",
             guarded([c](const Request& request, Response& response) {
               const int64_t id = shotIdOf(request);
               const int64_t frame = integerFrom(request.matches[2], "the frame");
               c.state.summary(id, farmClockSeconds());  // 404 for an unknown shot
               for (const auto& [outputFrame, chunk] : c.state.outputs(id)) {
                 if (outputFrame != frame) continue;
                 response.set_header("Cache-Control", "no-store");
                 response.set_content(c.thumbnails.png(chunk.sha256()), "image/png");
                 return;
               }
               throw std::out_of_range("shot " + std::to_string(id) + " has no frame " + std::to_string(frame) +
                                       " yet");
             }));
  server.Get("/api/workers", guarded([c](const Request&, Response& response) {
               const double now = farmClockSeconds();
               sendJson(response, workersJson(c.state.workers(now), c.state.runningTasks(), c.state.blocklist(0),
                                              c.state.settings().leaseSeconds, now));
             }));
}

void serveActions(httplib::Server& server, DashboardContext c) {
  server.Post(R"(/api/shots/([^/]+)/(cancel|pause|resume|retry))", action(c, [c](const Request& request, const json&) {
                using Control = ShotSummary (FarmState::*)(int64_t, double);
                static const std::map<std::string, Control> controls = {{"cancel", &FarmState::cancel},
                                                                        {"pause", &FarmState::pause},
                                                                        {"resume", &FarmState::resume},
                                                                        {"retry", &FarmState::retry}};
                const Control control = controls.at(request.matches[2]);
                return summaryReply((c.state.*control)(shotIdOf(request), farmClockSeconds()));
              }));
  server.Post(R"(/api/shots/([^/]+)/priority)", action(c, [c](const Request& request, const json& body) {
                const json priority = body.value("priority", json());
                if (!priority.is_number_integer() || priority.get<int64_t>() < INT32_MIN ||
                    priority.get<int64_t>() > INT32_MAX)
                  throw BadRequest("the body must be {\"priority\": N}, N a whole number");
                return summaryReply(
                    c.state.setPriority(shotIdOf(request), priority.get<int>(), farmClockSeconds()));
              }));
  server.Post(R"(/api/shots/([^/]+)/tasks/([^/]+)/requeue)", action(c, [c](const Request& request, const json&) {
                const int64_t task = idFrom(request.matches[2], "the task id");
                return summaryReply(c.state.requeueTask(shotIdOf(request), task, farmClockSeconds()));
              }));
  server.Post(R"(/api/shots/([^/]+)/frames/([^/]+)/requeue)", action(c, [c](const Request& request, const json&) {
                const int64_t frame = integerFrom(request.matches[2], "the frame");
                return summaryReply(c.state.requeueFrame(shotIdOf(request), frame, farmClockSeconds()));
              }));
  server.Post(R"(/api/shots/([^/]+)/blocklist/([^/]+)/clear)", action(c, [c](const Request& request, const json&) {
                const int64_t shot = shotIdOf(request);
                c.state.clearBlocklist(shot, idFrom(request.matches[2], "the worker id"), farmClockSeconds());
                return json{{"blocklist", blocklistJson(c.state.blocklist(shot))}};
              }));
}

}  // namespace

void serveDashboard(httplib::Server& server, DashboardContext context) {
  serveAssets(server);
  serveReads(server, context);
  serveActions(server, context);
}

}  // namespace pathfarm::farm
