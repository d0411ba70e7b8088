#include "proto/wire/tls.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pathfarm::farm {
namespace {

void fromEnvironment(std::string& value, const char* variable) {
  if (!value.empty()) return;
  if (const char* set = std::getenv(variable); set && *set) value = set;
}

void checkPair(const std::string& cert, const std::string& key, const char* whose) {
  if (cert.empty() != key.empty())
    throw std::runtime_error(std::string(whose) + ": give both a TLS certificate and its key, or neither");
}

}  // namespace

std::string readPemFile(const std::string& file, const char* what) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot read the " + what);
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().find("-----BEGIN ") == std::string::npos)
    throw std::runtime_error(file + ": the " + what + " is not in PEM format");
  return text.str();
}

ClientTls clientTlsFromEnvironment(ClientTls given) {
  fromEnvironment(given.caFile, "PATHFARM_TLS_CA");
  fromEnvironment(given.certFile, "PATHFARM_TLS_CERT");
  fromEnvironment(given.keyFile, "PATHFARM_TLS_KEY");
  checkPair(given.certFile, given.keyFile, "client");
  if (!given.enabled() && !given.certFile.empty())
    throw std::runtime_error("a client TLS certificate needs the CA of the scheduler's certificate too (--tls-ca)");
  return given;
}

std::shared_ptr<grpc::ServerCredentials> serverCredentials(const ServerTls& tls) {
  checkPair(tls.certFile, tls.keyFile, "scheduler");
  if (!tls.enabled()) {
    if (!tls.clientCaFile.empty()) throw std::runtime_error("--tls-client-ca needs --tls-cert and --tls-key");
    return grpc::InsecureServerCredentials();
  }
  grpc::SslServerCredentialsOptions options(
      tls.clientCaFile.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                               : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  options.pem_key_cert_pairs.push_back(
      {readPemFile(tls.keyFile, "TLS key"), readPemFile(tls.certFile, "TLS certificate")});
  if (!tls.clientCaFile.empty()) options.pem_root_certs = readPemFile(tls.clientCaFile, "client CA certificate");
  return grpc::SslServerCredentials(options);
}

std::shared_ptr<grpc::ChannelCredentials> channelCredentials(const ClientTls& tls) {
  if (!tls.enabled()) return grpc::InsecureChannelCredentials();
  grpc::SslCredentialsOptions options;
  options.pem_root_certs = readPemFile(tls.caFile, "CA certificate");
  if (!tls.certFile.empty()) {
    options.pem_cert_chain = readPemFile(tls.certFile, "TLS certificate");
    options.pem_private_key = readPemFile(tls.keyFile, "TLS key");
  }
  return grpc::SslCredentials(options);
}

}  // namespace pathfarm::farm
