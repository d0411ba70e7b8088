#pragma once
// The scheduler's HTTP side: GET /metrics in Prometheus' text format, computed from the
// same FarmState the gRPC services use at each request. Serves from a thread of its own
// until destroyed.
#include <functional>
#include <memory>
#include <string>

namespace pathfarm::farm {

class HttpServer {
 public:
  // Binds `listen` (HOST:PORT; port 0 takes any free port) and serves `metrics()` at
  // /metrics. Throws std::runtime_error when the address cannot be bound.
  HttpServer(const std::string& listen, std::function<std::string()> metrics);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

}  // namespace pathfarm::farm
