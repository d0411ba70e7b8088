#pragma once
// Channel and server settings every party shares, and the access token.
#include <grpcpp/grpcpp.h>

#include <memory>
#include <optional>
#include <string>

#include "proto/wire/tls.h"

namespace pathfarm::farm {

// The largest gRPC message either side accepts; chunk parts are 1 MiB.
inline constexpr int kMaxMessageBytes = 8 << 20;
// The largest chunk (a whole frame's EXR) accepted: a 16384x16384 frame of plain pt (six
// float channels, 6.4 GB before compression) comes to about 2.8 GB.
inline constexpr size_t kMaxChunkBytes = size_t{8} << 30;

// A channel to `address`, over TLS when `tls` names a CA (proto/wire/tls.h).
std::shared_ptr<grpc::Channel> makeChannel(const std::string& address, const ClientTls& tls = {});
// Whether `address` (HOST:PORT) reaches only this machine: localhost, 127.0.0.0/8 or [::1].
bool isLoopbackAddress(const std::string& address);
void configureServer(grpc::ServerBuilder& builder);

// Trouble a failed call shows with the connection itself, told apart so that it can be
// said in words that say what to do. gRPC reports both as a failure to connect.
enum class ConnectionTrouble {
  Other,
  TlsExpected,         // a plain connection the scheduler closed at once: it speaks TLS
  CertificateRefused,  // the TLS handshake failed: the certificate is not the CA's, or not the address's
};
ConnectionTrouble connectionTrouble(const grpc::Status& status, bool overTls);
// The status's message, followed by what to do about such trouble.
std::string explainedError(const grpc::Status& status, bool overTls);

// The shared token: from `tokenFile` if given, else the file named by PATHFARM_TOKEN_FILE,
// else the PATHFARM_TOKEN variable (set but empty is an error); empty when none is configured. Throws
// std::runtime_error if a named file cannot be read or is empty.
std::string loadToken(const std::string& tokenFile);

// 128 random bits as hex, from the kernel's generator: a local farm's token, a session key.
std::string randomToken();

// The metadata that carries the token and a worker's session ("ID:KEY").
inline constexpr const char* kTokenHeader = "x-pathfarm-token";
inline constexpr const char* kSessionHeader = "x-pathfarm-session";

void attachToken(grpc::ClientContext& context, const std::string& token);

// A registered worker's name for itself on every call after Register.
struct WorkerSession {
  int64_t workerId = 0;
  std::string key;
};
void attachSession(grpc::ClientContext& context, const WorkerSession& session);
std::string sessionHeaderValue(const WorkerSession& session);
// The session a call carries, or nothing (absent or malformed).
std::optional<WorkerSession> sessionOf(const grpc::ServerContext& context);
// True when no token is configured or the call carries it.
bool isAuthorized(const grpc::ServerContext& context, const std::string& token);

}  // namespace pathfarm::farm
