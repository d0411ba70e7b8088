#!/usr/bin/env python3
"""Checks that deploy/kubernetes/'s objects parse and reference each other consistently.

  check_refs.py FOLDER RENDERED

FOLDER holds the manifests and kustomization.yaml (and the files of the
secretGenerator: make_secrets.sh); RENDERED is `kubectl kustomize FOLDER`'s output, or an empty file, in
which case the kustomization's namespace and secretGenerator are applied here (names
without kustomize's hash suffix). Prints one line per check group; exits 1 listing every
problem found.
"""
import os
import sys

import yaml

problems = []


def problem(message):
    problems.append(message)


def load_all(path):
    with open(path, encoding="utf-8") as f:
        return [d for d in yaml.safe_load_all(f) if d is not None]


def parse_args(args):
    """--key=value and --key value into a dict; bare flags map to True."""
    out = {}
    i = 0
    while i < len(args):
        arg = args[i]
        if arg.startswith("--"):
            if "=" in arg:
                key, value = arg[2:].split("=", 1)
                out[key] = value
            elif i + 1 < len(args) and not args[i + 1].startswith("--"):
                out[arg[2:]] = args[i + 1]
                i += 1
            else:
                out[arg[2:]] = True
        i += 1
    return out


def host_port(address):
    host, _, port = address.rpartition(":")
    return host.strip("[]"), int(port)


def is_loopback(host):
    return host in ("localhost", "::1") or host.startswith("127.")


def subset(small, big):
    return all(big.get(k) == v for k, v in (small or {}).items())


def main():
    folder, rendered_path = sys.argv[1], sys.argv[2]

    # 1. Every file parses; every document names itself.
    files = sorted(f for f in os.listdir(folder) if f.endswith((".yaml", ".yml")))
    documents = 0
    for name in files:
        try:
            docs = load_all(os.path.join(folder, name))
        except yaml.YAMLError as e:
            problem(f"{name}: does not parse: {e}")
            continue
        for doc in docs:
            documents += 1
            if not isinstance(doc, dict) or not doc.get("apiVersion") or not doc.get("kind"):
                problem(f"{name}: a document without apiVersion or kind")
            elif doc["kind"] != "Kustomization" and not (doc.get("metadata") or {}).get("name"):
                problem(f"{name}: a {doc['kind']} without metadata.name")
    print(f"check_refs: {len(files)} files, {documents} documents parse (yaml.safe_load_all)")
    if problems:
        finish()

    kustomization = load_all(os.path.join(folder, "kustomization.yaml"))[0]
    namespace = kustomization.get("namespace")
    listed = set(kustomization.get("resources", []))
    manifests = set(files) - {"kustomization.yaml"}
    for missing in sorted(manifests - listed):
        problem(f"{missing} is not in kustomization.yaml's resources")
    for extra in sorted(listed - manifests):
        problem(f"kustomization.yaml lists {extra}, which is not in the folder")

    # 2. The objects as they would be applied.
    rendered = load_all(rendered_path) if os.path.getsize(rendered_path) else []
    if rendered:
        objects = rendered
        how = "kubectl kustomize's output"
    else:
        how = "the manifests with the kustomization applied here"
        objects = []
        for name in kustomization.get("resources", []):
            objects.extend(load_all(os.path.join(folder, name)))
        for generator in kustomization.get("secretGenerator", []):
            data = {}
            for source in generator.get("files", []):
                key, _, path = source.partition("=")
                path = path or key
                if not os.path.exists(os.path.join(folder, path)):
                    problem(f"secretGenerator {generator['name']}: file {path} is missing")
                data[key] = "..."
            for literal in generator.get("literals", []):
                data[literal.split("=", 1)[0]] = "..."
            objects.append({"apiVersion": "v1", "kind": "Secret", "metadata": {"name": generator["name"]}, "data": data})
        for o in objects:
            if o["kind"] != "Namespace" and namespace:
                o["metadata"]["namespace"] = namespace

    by_kind = {}
    for o in objects:
        by_kind.setdefault(o["kind"], {})[o["metadata"]["name"]] = o
    print(f"check_refs: {len(objects)} objects from {how}: " +
          ", ".join(f"{len(v)} {k}" for k, v in sorted(by_kind.items())))

    # Namespace and labels.
    namespaces = list(by_kind.get("Namespace", {}))
    if namespaces != [namespace]:
        problem(f"expected one Namespace named {namespace}, found {namespaces}")
    for o in objects:
        meta = o["metadata"]
        if o["kind"] != "Namespace" and meta.get("namespace") != namespace:
            problem(f"{o['kind']} {meta['name']} is in namespace {meta.get('namespace')}, not {namespace}")
        if o["kind"] != "Secret" and (meta.get("labels") or {}).get("app.kubernetes.io/name") != "pathfarm":
            problem(f"{o['kind']} {meta['name']} lacks the label app.kubernetes.io/name: pathfarm")

    secrets = by_kind.get("Secret", {})
    claims = by_kind.get("PersistentVolumeClaim", {})

    def secret_keys(name):
        s = secrets[name]
        return set((s.get("data") or {}).keys()) | set((s.get("stringData") or {}).keys())

    # Workloads: selectors, volumes, env, and which is which.
    workloads = {}
    for kind in ("Deployment", "StatefulSet"):
        for name, o in by_kind.get(kind, {}).items():
            spec = o["spec"]
            pod = spec["template"]
            labels = pod["metadata"].get("labels") or {}
            if not spec.get("selector", {}).get("matchLabels") or not subset(spec["selector"]["matchLabels"], labels):
                problem(f"{kind} {name}: selector.matchLabels is not a subset of its pod labels")
            volumes = {v["name"]: v for v in pod["spec"].get("volumes", [])}
            mounted = set()
            for c in pod["spec"]["containers"]:
                env = {e["name"]: e for e in c.get("env", [])}
                for e in env.values():
                    ref = (e.get("valueFrom") or {}).get("resourceFieldRef")
                    if ref and ref.get("containerName", c["name"]) != c["name"]:
                        problem(f"{kind} {name}: env {e['name']} reads resources of container {ref['containerName']}")
                    sref = (e.get("valueFrom") or {}).get("secretKeyRef")
                    if sref and (sref["name"] not in secrets or sref["key"] not in secret_keys(sref["name"])):
                        problem(f"{kind} {name}: env {e['name']} reads missing secret key {sref['name']}/{sref['key']}")
                for arg in c.get("args", []) + c.get("command", []):
                    start = arg.find("$(")
                    while start >= 0:
                        end = arg.index(")", start)
                        if arg[start + 2:end] not in env:
                            problem(f"{kind} {name}: argument {arg} uses $({arg[start + 2:end]}), which has no env")
                        start = arg.find("$(", end)
                for m in c.get("volumeMounts", []):
                    mounted.add(m["name"])
                    if m["name"] not in volumes:
                        problem(f"{kind} {name}: container {c['name']} mounts volume {m['name']}, which is not declared")
                role = (c.get("args") or [None])[0]
                if role in ("scheduler", "worker"):
                    if role in workloads:
                        problem(f"two {role} workloads")
                    workloads[role] = {"kind": kind, "name": name, "object": o, "labels": labels, "container": c,
                                       "volumes": volumes, "args": parse_args(c["args"][1:])}
            for vname, v in volumes.items():
                if vname not in mounted:
                    problem(f"{kind} {name}: volume {vname} is mounted by no container")
                if "persistentVolumeClaim" in v and v["persistentVolumeClaim"]["claimName"] not in claims:
                    problem(f"{kind} {name}: volume {vname} claims {v['persistentVolumeClaim']['claimName']}, which does not exist")
                if "secret" in v:
                    sname = v["secret"]["secretName"]
                    if sname not in secrets:
                        problem(f"{kind} {name}: volume {vname} uses secret {sname}, which does not exist")
                    else:
                        for item in v["secret"].get("items", []):
                            if item["key"] not in secret_keys(sname):
                                problem(f"{kind} {name}: volume {vname} uses key {item['key']}, not in secret {sname}")
    for role in ("scheduler", "worker"):
        if role not in workloads:
            problem(f"no workload runs `pathfarm {role}`")
    if problems:
        finish()
    print("check_refs: workloads: selectors match pod labels; every volume, claim, secret and secret key used exists; "
          "every $(VAR) has its env")

    def volume_of(workload, path):
        """The volume mounted at the longest prefix of path, and the path inside it."""
        best = None
        for m in workload["container"].get("volumeMounts", []):
            mount = m["mountPath"].rstrip("/")
            if path == mount or path.startswith(mount + "/"):
                if best is None or len(mount) > len(best[1]):
                    best = (m, mount)
        if best is None:
            return None, None
        return workload["volumes"][best[0]["name"]], path[len(best[1]) + 1:]

    def secret_file(workload, option, required=True):
        """The (secret, key) a file option names, reporting a path on no secret volume."""
        path = workload["args"].get(option)
        who = f"{workload['kind']} {workload['name']}"
        if not isinstance(path, str):
            if required:
                problem(f"{who}: no --{option}")
            return None
        volume, inside = volume_of(workload, path)
        if volume is None or "secret" not in volume:
            problem(f"{who}: --{option} {path} is not on a secret volume")
            return None
        items = {i["path"]: i["key"] for i in volume["secret"].get("items", [])}
        key = items.get(inside, inside if not items else None)
        name = volume["secret"]["secretName"]
        if key is None or name not in secrets or key not in secret_keys(name):
            problem(f"{who}: --{option} {path} names no key of secret {name}")
            return None
        return name, key

    def mounted_secret_keys(workload):
        """Every (secret, key) the workload's secret volumes put in its containers."""
        out = set()
        for volume in workload["volumes"].values():
            if "secret" not in volume or volume["secret"]["secretName"] not in secrets:
                continue
            name = volume["secret"]["secretName"]
            items = volume["secret"].get("items")
            keys = [i["key"] for i in items] if items else secret_keys(name)
            out.update((name, k) for k in keys)
        return out

    # The scheduler: ports, exposure (token, and TLS or --insecure), credentials, state on
    # the claim.
    s = workloads["scheduler"]
    ports = {p["name"]: p["containerPort"] for p in s["container"].get("ports", [])}
    listen_host, listen_port = host_port(s["args"]["listen"])
    if ports.get("grpc") != listen_port:
        problem(f"scheduler: --listen port {listen_port} is not its containerPort grpc ({ports.get('grpc')})")
    if ("tls-cert" in s["args"]) != ("tls-key" in s["args"]):
        problem("scheduler: --tls-cert and --tls-key go together (the scheduler would refuse to start)")
    tls = "tls-cert" in s["args"] and "tls-key" in s["args"]
    if "tls-client-ca" in s["args"] and not tls:
        problem("scheduler: --tls-client-ca without --tls-cert and --tls-key (the scheduler would refuse to start)")
    exposure_ok = tls or s["args"].get("insecure") is True
    addresses = [("--listen", listen_host)]
    if "http" in s["args"]:
        http_host, http_port = host_port(s["args"]["http"])
        if ports.get("http") != http_port:
            problem(f"scheduler: --http port {http_port} is not its containerPort http ({ports.get('http')})")
        addresses.append(("--http", http_host))
    for option, host in addresses:
        if not is_loopback(host) and not exposure_ok:
            problem(f"scheduler: {option} beyond loopback without TLS (--tls-cert, --tls-key) or --insecure "
                    "(the scheduler would refuse to start)")
    client_token = secret_file(s, "token-file")
    worker_token = secret_file(s, "worker-token-file", required=False)
    scheduler_key = None
    if tls:
        secret_file(s, "tls-cert")
        scheduler_key = secret_file(s, "tls-key")
    if "tls-client-ca" in s["args"]:
        secret_file(s, "tls-client-ca")
    for option in ("db", "store"):
        volume, _ = volume_of(s, s["args"].get(option, ""))
        if volume is None or "persistentVolumeClaim" not in volume:
            problem(f"scheduler: --{option} {s['args'].get(option)} is not on the persistent volume")
    spec = s["object"]["spec"]
    if spec.get("replicas", 1) != 1:
        problem("scheduler: replicas must be 1 (one database serves one scheduler)")
    if s["kind"] == "Deployment" and spec.get("strategy", {}).get("type") != "Recreate":
        problem("scheduler: a Deployment needs strategy Recreate (the old pod must let go of the database first)")

    # The Service: selects the scheduler only, targets its ports.
    services = by_kind.get("Service", {})
    grpc_services = []
    for name, svc in services.items():
        selector = svc["spec"].get("selector") or {}
        if not subset(selector, s["labels"]):
            problem(f"Service {name}: selector {selector} does not select the scheduler's pods")
        if subset(selector, workloads["worker"]["labels"]):
            problem(f"Service {name}: selector {selector} also selects the workers")
        for p in svc["spec"]["ports"]:
            target = p.get("targetPort", p["port"])
            number = ports.get(target) if isinstance(target, str) else target
            if number not in ports.values():
                problem(f"Service {name}: port {p.get('name')} targets {target}, not a scheduler containerPort")
            if number == ports.get("grpc"):
                grpc_services.append((name, p["port"]))

    # The workers: --scheduler names the Service and its gRPC port; token.
    w = workloads["worker"]
    w_host, w_port = host_port(w["args"].get("scheduler", ":0"))
    matches = [(n, p) for n, p in grpc_services
               if w_host in (n, f"{n}.{namespace}", f"{n}.{namespace}.svc", f"{n}.{namespace}.svc.cluster.local")
               and w_port == p]
    if not matches:
        problem(f"worker: --scheduler {w_host}:{w_port} is not a Service port targeting the scheduler's gRPC port "
                f"(those are {grpc_services})")
    shown = secret_file(w, "token-file")
    expected = worker_token or client_token
    if shown and expected and shown != expected:
        which = "--worker-token-file" if worker_token else "--token-file"
        problem(f"worker: --token-file is {shown[0]}/{shown[1]}, not the scheduler's {which} "
                f"{expected[0]}/{expected[1]} (the scheduler would refuse the workers)")
    if tls:
        secret_file(w, "tls-ca")
    elif "tls-ca" in w["args"]:
        problem("worker: --tls-ca, but the scheduler serves no TLS (the workers could not connect)")
    if "tls-client-ca" in s["args"]:
        secret_file(w, "tls-cert")
        secret_file(w, "tls-key")
    exposed = mounted_secret_keys(w)
    if scheduler_key and scheduler_key in exposed:
        problem(f"worker: mounts the scheduler's private key {scheduler_key[0]}/{scheduler_key[1]}")
    if worker_token and client_token and client_token in exposed:
        problem(f"worker: mounts the clients' token {client_token[0]}/{client_token[1]}, "
                "which workers with a token of their own do not need")

    # The NetworkPolicy: selects the scheduler, names its ports, lets the workers in.
    for name, policy in by_kind.get("NetworkPolicy", {}).items():
        if not subset(policy["spec"]["podSelector"].get("matchLabels"), s["labels"]):
            problem(f"NetworkPolicy {name}: does not select the scheduler's pods")
        workers_in = False
        for rule in policy["spec"].get("ingress", []):
            for p in rule.get("ports", []):
                if isinstance(p["port"], str) and p["port"] not in ports:
                    problem(f"NetworkPolicy {name}: port {p['port']} is not a scheduler port name")
            for source in rule.get("from", []):
                if subset((source.get("podSelector") or {}).get("matchLabels"), w["labels"]):
                    workers_in = True
        if not workers_in:
            problem(f"NetworkPolicy {name}: does not let the workers in")

    images = {c["image"].split("@")[0].rsplit(":", 1)[0] for c in (s["container"], w["container"])}
    if len(images) != 1:
        problem(f"the scheduler and the workers run different images: {images}")
    if problems:
        finish()
    protection = "TLS" if tls else "--insecure"
    tokens = "a client token and a worker token" if worker_token else "one token"
    print(f"check_refs: scheduler listens on its grpc port {listen_port} beyond loopback with {protection} and "
          f"{tokens}; Service {matches[0][0]}:{matches[0][1]} targets it; workers use --scheduler {w_host}:{w_port}"
          f"{' trusting --tls-ca' if tls else ''} with the scheduler's worker credential and no key of the "
          "scheduler's; NetworkPolicy selects the scheduler and lets the workers in; one image")
    finish()


def finish():
    if problems:
        for p in problems:
            print(f"check_refs: PROBLEM: {p}", file=sys.stderr)
        sys.exit(1)
    sys.exit(0)


if __name__ == "__main__":
    main()
