#include "scheduler/http/http_server.h"

#include <httplib.h>
#include <nlohmann/json.hpp>
#include <openssl/crypto.h>
#include <spdlog/spdlog.h>

#include <stdexcept>
#include <thread>

#include "scheduler/http/dashboard_assets.h"

namespace pathfarm::farm {
namespace {

// Whether the request carries the token; compared in constant time, so the timing of a
// refusal does not tell how much of a guess was right.
bool carriesToken(const httplib::Request& request, const std::string& token) {
  const std::string header = request.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (header.rfind(prefix, 0) != 0) return false;
  const std::string_view offered = std::string_view(header).substr(prefix.size());
  return offered.size() == token.size() && CRYPTO_memcmp(offered.data(), token.data(), token.size()) == 0;
}

void refuse(httplib::Response& response) {
  response.status = 401;
  response.set_header("WWW-Authenticate", "Bearer");
  response.set_content(nlohmann::json{{"error", "this farm requires its access token (Authorization: Bearer TOKEN)"}}
                           .dump(),
                       "application/json");
}

// What anyone who reaches the port may read: the page's files and the farm's counts.
bool isOpen(const httplib::Request& request) {
  return request.method == "GET" && (request.path == "/metrics" || findDashboardAsset(request.path));
}

}  // namespace

struct HttpServer::Impl {
  std::unique_ptr<httplib::Server> server;
  std::thread thread;
};

namespace {

std::unique_ptr<httplib::Server> makeServer(const ServerTls& tls) {
  if (!tls.enabled()) return std::make_unique<httplib::Server>();
  readPemFile(tls.certFile, "TLS certificate");  // a clear message before OpenSSL's silence
  readPemFile(tls.keyFile, "TLS key");
  auto server = std::make_unique<httplib::SSLServer>(tls.certFile.c_str(), tls.keyFile.c_str());
  if (!server->is_valid())
    throw std::runtime_error(tls.certFile + ", " + tls.keyFile + ": not a usable certificate and key for HTTPS");
  return server;
}

}  // namespace

HttpServer::HttpServer(const std::string& listen, const std::string& token, const ServerTls& tls,
                       const HttpRoutes& routes)
    : impl_(std::make_unique<Impl>()) {
  impl_->server = makeServer(tls);
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
  httplib::Server& server = *impl_->server;
  server.set_pre_routing_handler([token](const httplib::Request& request, httplib::Response& response) {
    if (token.empty() || isOpen(request) || carriesToken(request, token))
      return httplib::Server::HandlerResponse::Unhandled;
    refuse(response);
    return httplib::Server::HandlerResponse::Handled;
  });
  // Errors without a body of their own (no such path, wrong method) still answer in JSON.
  server.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request& request,
                                                                    httplib::Response& response) {
    if (!response.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    const std::string message = response.status == 404
                                    ? "no " + request.method + " " + request.path + " here"
                                    : "cannot answer " + request.method + " " + request.path + " (HTTP status " +
                                          std::to_string(response.status) + ")";
    response.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
    return httplib::Server::HandlerResponse::Handled;
  }));
  routes(server);
  port_ = port == 0 ? server.bind_to_any_port(host) : (server.bind_to_port(host, port) ? port : -1);
  if (port_ <= 0) throw std::runtime_error("cannot serve HTTP on " + listen);
  impl_->thread = std::thread([this] { impl_->server->listen_after_bind(); });
  const std::string url = (tls.enabled() ? "https://" : "http://") + (host.find(':') == std::string::npos ? host : "[" + host + "]") + ":" +
                          std::to_string(port_);
  spdlog::info("dashboard on {}/{} and metrics on {}/metrics", url,
               token.empty() ? "" : " (its API asks for the access token)", url);
}

HttpServer::~HttpServer() {
  impl_->server->stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

void serveMetrics(httplib::Server& server, std::function<std::string()> metrics) {
  server.Get("/metrics", [metrics = std::move(metrics)](const httplib::Request&, httplib::Response& response) {
    try {
      response.set_content(metrics(), "text/plain; version=0.0.4; charset=utf-8");
    } catch (const std::exception& e) {
      response.status = 500;
      response.set_content(std::string("cannot read the farm's state: ") + e.what() + "\n", "text/plain");
    }
  });
}

}  // namespace pathfarm::farm
