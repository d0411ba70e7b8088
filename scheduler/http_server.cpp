#include "scheduler/http_server.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <stdexcept>
#include <thread>

namespace pathfarm::farm {

struct HttpServer::Impl {
  httplib::Server server;
  std::thread thread;
};

HttpServer::HttpServer(const std::string& listen, std::function<std::string()> metrics)
    : impl_(std::make_unique<Impl>()) {
  const size_t colon = listen.rfind(':');
  if (colon == std::string::npos) throw std::runtime_error("--http " + listen + ": expected HOST:PORT");
  std::string host = listen.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  int port = 0;
  try {
    port = std::stoi(listen.substr(colon + 1));
  } catch (const std::exception&) {
    throw std::runtime_error("--http " + listen + ": the port is not a number");
  }
  impl_->server.Get("/metrics", [metrics = std::move(metrics)](const httplib::Request&, httplib::Response& response) {
    try {
      response.set_content(metrics(), "text/plain; version=0.0.4; charset=utf-8");
    } catch (const std::exception& e) {
      response.status = 500;
      response.set_content(std::string("cannot read the farm's state: ") + e.what() + "\n", "text/plain");
    }
  });
  port_ = port == 0 ? impl_->server.bind_to_any_port(host) : (impl_->server.bind_to_port(host, port) ? port : -1);
  if (port_ <= 0) throw std::runtime_error("cannot serve HTTP on " + listen);
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
  spdlog::info("metrics on http://{}:{}/metrics", host, port_);
}

HttpServer::~HttpServer() {
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

}  // namespace pathfarm::farm
