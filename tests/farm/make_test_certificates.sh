#!/usr/bin/env bash
# Makes a throwaway CA and, signed by it, a server certificate for 127.0.0.1/localhost
# and a client certificate, for the farm's TLS tests: DIR/{ca,server,client}.{pem,key},
# and a second, unrelated CA (DIR/other-ca.pem) that must not be trusted.
#
# Usage: tests/farm/make_test_certificates.sh DIR
set -euo pipefail
dir=${1:?usage: $0 DIR}
mkdir -p "$dir"
cd "$dir"
key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1" 2>/dev/null; }
ca() {
  key "$1.key"
  openssl req -x509 -new -key "$1.key" -out "$1.pem" -days 2 -subj "/CN=pathfarm test $1" 2>/dev/null
}
signed() {  # name, subject, extensions
  key "$1.key"
  openssl req -new -key "$1.key" -out "$1.csr" -subj "$2" 2>/dev/null
  printf '%s\n' "$3" > "$1.ext"
  openssl x509 -req -in "$1.csr" -CA ca.pem -CAkey ca.key -CAcreateserial -out "$1.pem" -days 2 \
    -extfile "$1.ext" 2>/dev/null
}
ca ca
ca other-ca
signed server "/CN=localhost" "subjectAltName=IP:127.0.0.1,DNS:localhost
extendedKeyUsage=serverAuth"
signed client "/CN=pathfarm test client" "extendedKeyUsage=clientAuth"
