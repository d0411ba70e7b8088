#pragma once
// TLS for the farm's gRPC channels (PEM files). A scheduler serves with a certificate and
// key, and may require client certificates signed by a CA it names; a client or worker
// trusts the CA that signed the scheduler's certificate, and may present its own.
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace pathfarm::farm {

struct ServerTls {
  std::string certFile, keyFile;  // both or neither; neither: no TLS
  std::string clientCaFile;       // non-empty: every caller shows a certificate it signed
  bool enabled() const { return !certFile.empty(); }
};

struct ClientTls {
  std::string caFile;             // the CA the scheduler's certificate chains to; empty: no TLS
  std::string certFile, keyFile;  // this party's certificate, for a scheduler that asks
  bool enabled() const { return !caFile.empty(); }
};

// The files given, else PATHFARM_TLS_CA, PATHFARM_TLS_CERT and PATHFARM_TLS_KEY for the
// ones not given. Throws std::runtime_error when only one of certificate and key is named.
ClientTls clientTlsFromEnvironment(ClientTls given);

// Read the PEM files; throw std::runtime_error naming a file that cannot be read or a
// certificate given without its key.
std::shared_ptr<grpc::ServerCredentials> serverCredentials(const ServerTls& tls);
std::shared_ptr<grpc::ChannelCredentials> channelCredentials(const ClientTls& tls);

// A PEM file's text; throws std::runtime_error naming the file.
std::string readPemFile(const std::string& file, const char* what);

}  // namespace pathfarm::farm
