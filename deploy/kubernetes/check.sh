#!/usr/bin/env bash
# Checks deploy/kubernetes/ without a cluster:
#
#   1. every YAML file parses (PyYAML safe_load_all) and every document has apiVersion,
#      kind and metadata.name; kustomization.yaml lists every manifest in the folder;
#   2. makes throw-away secret files with make_secrets.sh in a copy of the folder (tokens,
#      a CA, the scheduler's certificate, which must verify for the Service's name), then
#      renders the kustomization with `kubectl kustomize` when kubectl is here (offline:
#      it needs no cluster); without kubectl, applies its namespace and secretGenerator
#      by hand (the same names, minus the hash suffix);
#   3. checks that the rendered objects reference each other consistently (check_refs.py):
#      selectors and pod labels, the Service's target ports and the scheduler's
#      container ports and --listen/--http, beyond loopback a token file and TLS
#      (--tls-cert/--tls-key) or --insecure, the workers' --scheduler naming the Service
#      and its gRPC port, the workers' --tls-ca when the scheduler has TLS, the workers'
#      --token-file being the scheduler's --worker-token-file (or its --token-file), the
#      workers mounting neither the clients' token nor the scheduler's key, every secret,
#      secret key, claim and volume that is referenced exists, $(VAR) arguments have
#      their env, the NetworkPolicy selects the scheduler and names its ports, one
#      namespace for all.
#
# Not checked: the objects against the API server's schemas (no cluster here, and
# `kubectl apply --dry-run=client` needs one for its OpenAPI), and that pods run.
# Usage: deploy/kubernetes/check.sh [--no-kubectl]   (installs python3-yaml with apt-get
# if no python3 here can import yaml; --no-kubectl tries the reading without kubectl;
# needs openssl)
set -euo pipefail
use_kubectl=1
case ${1:-} in
  "") ;;
  --no-kubectl) use_kubectl="" ;;
  *) echo "usage: $0 [--no-kubectl]" >&2; exit 2 ;;
esac

here=$(cd "$(dirname "$0")" && pwd)
fail() {
  echo "kubernetes check: FAILED: $*" >&2
  exit 1
}

python=""
for candidate in python3 /usr/bin/python3; do
  if command -v "$candidate" > /dev/null && "$candidate" -c 'import yaml' 2> /dev/null; then
    python=$(command -v "$candidate")
    break
  fi
done
if [ -z "$python" ]; then
  [ "$(id -u)" -eq 0 ] || fail "no python3 with PyYAML: apt-get install python3-yaml (as root)"
  echo "kubernetes check: installing Debian's python3-yaml"
  DEBIAN_FRONTEND=noninteractive apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-yaml
  python=/usr/bin/python3
  "$python" -c 'import yaml' || fail "python3-yaml installed but /usr/bin/python3 cannot import yaml"
fi

tmp=$(mktemp -d /tmp/pathfarm-k8s-check.XXXXXX)
trap 'rm -rf "$tmp"' EXIT

# A copy of the folder with throw-away secrets, so the real folder is never touched.
cp -r "$here" "$tmp/kubernetes"
(cd "$tmp/kubernetes" && rm -f token worker-token ca.crt ca.key tls.crt tls.key)
"$here/make_secrets.sh" "$tmp/kubernetes" > "$tmp/make_secrets.out" 2>&1 ||
  fail "make_secrets.sh: $(cat "$tmp/make_secrets.out")"
for f in token worker-token ca.crt tls.crt tls.key; do
  [ -s "$tmp/kubernetes/$f" ] || fail "make_secrets.sh did not make $f"
done
openssl verify -CAfile "$tmp/kubernetes/ca.crt" -verify_hostname pathfarm-scheduler.pathfarm.svc \
  "$tmp/kubernetes/tls.crt" > /dev/null 2>&1 || fail "tls.crt does not verify for pathfarm-scheduler.pathfarm.svc"
again=$("$here/make_secrets.sh" "$tmp/kubernetes" 2>&1) || fail "a second make_secrets.sh: $again"
[[ "$again" == *"kept every file"* ]] || fail "a second make_secrets.sh changed a file: $again"
echo "kubernetes check: make_secrets.sh made the Secret's files; tls.crt verifies against ca.crt for the Service"

if [ -n "$use_kubectl" ] && command -v kubectl > /dev/null && kubectl kustomize --help > /dev/null 2>&1; then
  kubectl kustomize "$tmp/kubernetes" > "$tmp/rendered.yaml" 2> "$tmp/kustomize.err" ||
    fail "kubectl kustomize: $(cat "$tmp/kustomize.err")"
  renderer="kubectl kustomize ($(kubectl version --client 2> /dev/null | grep -i kustomize | head -1))"
else
  renderer="check_refs.py's own reading of kustomization.yaml (no kubectl)"
  : > "$tmp/rendered.yaml"
fi

"$python" "$here/check_refs.py" "$tmp/kubernetes" "$tmp/rendered.yaml" || fail "see above"
echo "kubernetes check: rendered with $renderer"
echo "kubernetes check: PASSED"
