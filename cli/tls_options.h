#pragma once
// The TLS options every party that connects to a scheduler takes (clients and workers).
#include <CLI/CLI.hpp>

#include "proto/wire/tls.h"

namespace pathfarm {

inline void addClientTlsOptions(CLI::App* command, farm::ClientTls& tls) {
  command->add_option("--tls-ca", tls.caFile,
                      "PEM CA of the scheduler's certificate: connect over TLS (or PATHFARM_TLS_CA)");
  command->add_option("--tls-cert", tls.certFile,
                      "PEM certificate to show a scheduler that asks for one (or PATHFARM_TLS_CERT)");
  command->add_option("--tls-key", tls.keyFile, "PEM private key of --tls-cert (or PATHFARM_TLS_KEY)");
}

}  // namespace pathfarm
