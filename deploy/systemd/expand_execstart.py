#!/usr/bin/env python3
"""Prints a unit's ExecStart= as systemd would run it, one argument per NUL-terminated
field: used by check.sh to run the units' command lines on a machine without systemd.

  expand_execstart.py UNIT_FILE --instance I --host H --state DIR --cache DIR
                      --root DIR --env FILE [--env FILE ...]

Handles what the pathfarm units use: line continuations, the specifiers %i %I %H %S %C %%,
EnvironmentFile= lines KEY=value (later files override earlier ones, missing "-" files
skipped by the caller), "${VAR}" (one argument, empty if unset) and "$VAR" alone (split
at whitespace into zero or more arguments). The executable gets --root prefixed.
"""
import argparse
import re
import sys


def read_env(paths):
    env = {}
    for path in paths:
        with open(path, encoding="utf-8") as f:
            for line in f:
                line = line.strip()
                if not line or line[0] in "#;":
                    continue
                key, sep, value = line.partition("=")
                if not sep or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key.strip()):
                    sys.exit(f"{path}: not KEY=value: {line}")
                value = value.strip()
                if len(value) >= 2 and value[0] == value[-1] and value[0] in "'\"":
                    value = value[1:-1]
                env[key.strip()] = value
    return env


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("unit")
    parser.add_argument("--instance", default="")
    parser.add_argument("--host", required=True)
    parser.add_argument("--state", required=True)
    parser.add_argument("--cache", required=True)
    parser.add_argument("--root", default="")
    parser.add_argument("--env", action="append", default=[])
    a = parser.parse_args()

    text = open(a.unit, encoding="utf-8").read().replace("\\\n", " ")
    lines = [l for l in text.splitlines() if l.startswith("ExecStart=")]
    if len(lines) != 1:
        sys.exit(f"{a.unit}: expected one ExecStart=, found {len(lines)}")
    command = lines[0][len("ExecStart="):]
    specifiers = {"i": a.instance, "I": a.instance, "H": a.host, "S": a.state, "C": a.cache, "%": "%"}

    def specifier(m):
        if m.group(1) not in specifiers:
            sys.exit(f"{a.unit}: specifier %{m.group(1)} is not handled here")
        return specifiers[m.group(1)]

    command = re.sub(r"%(.)", specifier, command)
    env = read_env(a.env)
    if '"' in command or "'" in command:
        sys.exit(f"{a.unit}: quotes in ExecStart= are not handled here")
    argv = []
    for word in command.split():
        whole = re.fullmatch(r"\$([A-Za-z_][A-Za-z0-9_]*)", word)
        if whole:
            argv.extend(env.get(whole.group(1), "").split())
        else:
            argv.append(re.sub(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}", lambda m: env.get(m.group(1), ""), word))
    argv[0] = a.root + argv[0]
    sys.stdout.write("".join(arg + "\0" for arg in argv))


if __name__ == "__main__":
    main()
