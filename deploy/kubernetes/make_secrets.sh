#!/usr/bin/env bash
# Makes the files kustomization.yaml's secretGenerator reads (git ignores them all):
#
#   token         the clients' access token: the scheduler's --token-file; give a copy to
#                 whoever submits shots (PATHFARM_TOKEN_FILE)
#   worker-token  the workers' own token: the scheduler's --worker-token-file and the
#                 workers' --token-file (it cannot submit, fetch or cancel anything)
#   ca.crt        the certificate of a new CA: the workers' --tls-ca; give a copy to
#                 whoever submits (PATHFARM_TLS_CA)
#   tls.crt       the scheduler's certificate, signed by that CA, for every name the
#                 scheduler is reached by: the Service (SERVICE, SERVICE.NAMESPACE,
#                 SERVICE.NAMESPACE.svc, SERVICE.NAMESPACE.svc.cluster.local) and, for
#                 `kubectl port-forward`, localhost and 127.0.0.1
#   tls.key       its private key
#   ca.key        the CA's private key. Nothing in the kustomization reads it: it is
#                 needed only to sign more certificates (client certificates for
#                 --tls-client-ca, a renewed tls.crt). Move it somewhere safe.
#
# A file already there is kept, so running this again changes nothing; delete a file to
# make it anew (a new ca.crt also makes a new tls.crt and tls.key). The Secret's name
# carries a hash of its content, so `kubectl apply -k` after a change rolls both
# Deployments.
#
# Usage: deploy/kubernetes/make_secrets.sh [FOLDER]   (default: this script's folder)
#   PATHFARM_NAMESPACE (default pathfarm), PATHFARM_SERVICE (default pathfarm-scheduler),
#   PATHFARM_CERT_DAYS (default 825): must match kustomization.yaml and service.yaml.
# Needs openssl. These are the files of a self-made CA; with your organisation's CA,
# put its certificate in ca.crt and the scheduler's certificate and key it signed in
# tls.crt and tls.key instead.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
folder=${1:-$here}
namespace=${PATHFARM_NAMESPACE:-pathfarm}
service=${PATHFARM_SERVICE:-pathfarm-scheduler}
days=${PATHFARM_CERT_DAYS:-825}
die() {
  echo "make_secrets.sh: $*" >&2
  exit 2
}
[ -d "$folder" ] || die "$folder is not a folder"
command -v openssl > /dev/null || die "openssl is needed (apt-get install openssl)"
cd "$folder"
umask 077

made=()
for name in token worker-token; do
  if [ ! -e "$name" ]; then
    head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' > "$name"
    made+=("$name")
  fi
done

# EC P-256 keys; `openssl req -x509` marks the CA's certificate CA:TRUE.
new_key() { openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:prime256v1 -out "$1" 2> /dev/null; }
new_ca=""
if [ ! -e ca.crt ]; then
  new_key ca.key
  openssl req -x509 -new -key ca.key -out ca.crt -days "$days" -subj "/CN=pathfarm CA ($namespace)" 2> /dev/null
  new_ca=1
  made+=(ca.crt ca.key)
fi
if [ -n "$new_ca" ] || [ ! -e tls.crt ] || [ ! -e tls.key ]; then
  [ -e ca.key ] || die "cannot sign tls.crt: ca.key is not here (put it back, or delete ca.crt for a new CA)"
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  new_key tls.key
  openssl req -new -key tls.key -out "$work/tls.csr" -subj "/CN=$service.$namespace.svc" 2> /dev/null
  names="DNS:$service,DNS:$service.$namespace,DNS:$service.$namespace.svc"
  names+=",DNS:$service.$namespace.svc.cluster.local,DNS:localhost,IP:127.0.0.1"
  printf 'subjectAltName=%s\nextendedKeyUsage=serverAuth\n' "$names" > "$work/tls.ext"
  openssl x509 -req -in "$work/tls.csr" -CA ca.crt -CAkey ca.key -CAcreateserial -CAserial "$work/ca.srl" \
    -days "$days" -extfile "$work/tls.ext" -out tls.crt 2> /dev/null
  openssl verify -CAfile ca.crt -verify_hostname "$service" tls.crt > /dev/null ||
    die "tls.crt does not verify against ca.crt for $service"
  made+=(tls.crt tls.key)
fi

if ((${#made[@]})); then
  echo "make_secrets.sh: made ${made[*]} in $folder"
else
  echo "make_secrets.sh: kept every file in $folder"
fi
if [ -e ca.key ]; then
  echo "make_secrets.sh: ca.key is read by nothing here: move it somewhere safe"
fi
