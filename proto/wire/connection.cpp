#include "proto/wire/connection.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pathfarm::farm {
namespace {

// Compares without an early exit, so timing does not reveal how much of a guess matched
// (a token's length is no secret worth guarding).
bool equalInConstantTime(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < a.size(); ++i) difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  return difference == 0;
}

std::string readTokenFile(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot read the token file");
  std::ostringstream text;
  text << in.rdbuf();
  std::string token = text.str();
  token.erase(token.find_last_not_of(" \t\r\n") + 1);
  if (token.empty()) throw std::runtime_error(file + ": the token file is empty");
  return token;
}

}  // namespace

std::shared_ptr<grpc::Channel> makeChannel(const std::string& address, const ClientTls& tls) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(kMaxMessageBytes);
  arguments.SetMaxSendMessageSize(kMaxMessageBytes);
  // gRPC waits up to 2 minutes between connection attempts by default; a farm's parties
  // retry every 5 s at most themselves (worker/backoff.h), and so does the connection.
  arguments.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 5000);
  return grpc::CreateCustomChannel(address, channelCredentials(tls), arguments);
}

bool isLoopbackAddress(const std::string& address) {
  const size_t colon = address.rfind(':');
  const std::string host = address.substr(0, colon == std::string::npos ? address.size() : colon);
  return host == "localhost" || host.rfind("127.", 0) == 0 || host == "[::1]";
}

void configureServer(grpc::ServerBuilder& builder) {
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
}

std::string loadToken(const std::string& tokenFile) {
  if (!tokenFile.empty()) return readTokenFile(tokenFile);
  if (const char* file = std::getenv("PATHFARM_TOKEN_FILE"); file && *file) return readTokenFile(file);
  if (const char* token = std::getenv("PATHFARM_TOKEN")) {
    // An empty value must not turn access control off in silence.
    if (!*token) throw std::runtime_error("PATHFARM_TOKEN is set but empty: unset it, or give the farm's token");
    return token;
  }
  return "";
}

std::string randomToken() {
  std::ifstream random("/dev/urandom", std::ios::binary);
  unsigned char bytes[16];
  if (!random.read(reinterpret_cast<char*>(bytes), sizeof bytes)) throw std::runtime_error("cannot read /dev/urandom");
  static const char* hex = "0123456789abcdef";
  std::string token;
  for (unsigned char b : bytes) {
    token.push_back(hex[b >> 4]);
    token.push_back(hex[b & 15]);
  }
  return token;
}

void attachToken(grpc::ClientContext& context, const std::string& token) {
  if (!token.empty()) context.AddMetadata(kTokenHeader, token);
}

void attachSession(grpc::ClientContext& context, const WorkerSession& session) {
  if (session.workerId > 0) context.AddMetadata(kSessionHeader, sessionHeaderValue(session));
}

std::string sessionHeaderValue(const WorkerSession& session) {
  return std::to_string(session.workerId) + ":" + session.key;
}

std::optional<WorkerSession> sessionOf(const grpc::ServerContext& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find(kSessionHeader);
  if (it == metadata.end()) return std::nullopt;
  const std::string text(it->second.data(), it->second.size());
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon > 18) return std::nullopt;
  WorkerSession session;
  for (size_t i = 0; i < colon; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    session.workerId = session.workerId * 10 + (text[i] - '0');
  }
  session.key = text.substr(colon + 1);
  return session;
}

bool isAuthorized(const grpc::ServerContext& context, const std::string& token) {
  if (token.empty()) return true;
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find(kTokenHeader);
  if (it == metadata.end()) return false;
  return equalInConstantTime(std::string_view(it->second.data(), it->second.size()), token);
}

ConnectionTrouble connectionTrouble(const grpc::Status& status, bool overTls) {
  const std::string& message = status.error_message();
  // Only a call that never connected: a scheduler that dies mid-call closes the socket too.
  const bool neverConnected = message.find("failed to connect to all addresses") != std::string::npos;
  if (!overTls && neverConnected && status.error_code() == grpc::StatusCode::UNAVAILABLE &&
      message.find("Socket closed") != std::string::npos)
    return ConnectionTrouble::TlsExpected;
  // Only the certificate check: other handshake failures (a reset, a plain scheduler) may pass.
  if (overTls && (message.find("certificate verify failed") != std::string::npos ||
                  message.find("CERTIFICATE_VERIFY_FAILED") != std::string::npos))
    return ConnectionTrouble::CertificateRefused;
  return ConnectionTrouble::Other;
}

std::string explainedError(const grpc::Status& status, bool overTls) {
  switch (connectionTrouble(status, overTls)) {
    case ConnectionTrouble::TlsExpected:
      return status.error_message() +
             " (the scheduler closed a plain connection at once: it speaks TLS; give the CA of its certificate with "
             "--tls-ca FILE or PATHFARM_TLS_CA)";
    case ConnectionTrouble::CertificateRefused:
      return status.error_message() +
             " (the scheduler's certificate was refused: --tls-ca must name the CA that signed it, and the address "
             "must be a name or IP the certificate lists)";
    case ConnectionTrouble::Other:
      break;
  }
  return status.error_message();
}

}  // namespace pathfarm::farm
