#pragma once
// The scheduler's HTTP side: the dashboard (its page and its /api) and GET /metrics in
// Prometheus' text format, all computed from the same FarmState the gRPC services use
// at each request. Serves from a thread of its own until destroyed.
#include <functional>
#include <memory>
#include <string>

#include "proto/wire/tls.h"

namespace httplib {
class Server;
}

namespace pathfarm::farm {

// Installs handlers on the server before it starts serving.
using HttpRoutes = std::function<void(httplib::Server&)>;

class HttpServer {
 public:
  // Binds `listen` (HOST:PORT; port 0 takes any free port) and serves what `routes`
  // installs. With a `token`, every request must carry `Authorization: Bearer TOKEN`, else
  // it gets 401, but for the dashboard's page (its HTML, script and style, which hold no
  // farm data) and /metrics (counts for Prometheus, scraped without credentials as before
  // the dashboard). Throws std::runtime_error when the address cannot be bound.
  // With a certificate in `tls`, it serves HTTPS (no client certificate is asked for: the
  // token guards the API).
  HttpServer(const std::string& listen, const std::string& token, const ServerTls& tls, const HttpRoutes& routes);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

// GET /metrics: `metrics()` in Prometheus' text format.
void serveMetrics(httplib::Server& server, std::function<std::string()> metrics);

}  // namespace pathfarm::farm
