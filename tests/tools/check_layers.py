#!/usr/bin/python3
"""The layers of docs/architecture.md, checked on every #include line.

    check_layers.py REPOSITORY_ROOT

Dependencies run one way (../shared/docs/architecture.md):

    proto ← coupler;  proto ← base;  fluid, solid ← base + coupler;  launcher ← base + coupler

(proto/ holds the schemas of both the coupling messages and the case file, so base reads it too). Every
quoted include is written from the repository root ("fluid/scheme.hpp") and names a file that exists; the
coupling library's public header includes no ZeroMQ or protobuf header. tests/ may include anything.
Exits 1 listing every include against the allowed direction.
"""
import os
import re
import sys

ALLOWED = {
    "proto": {"proto"},
    "coupler": {"coupler", "proto"},
    "base": {"base", "proto"},
    "fluid": {"fluid", "base", "coupler", "proto"},
    "solid": {"solid", "base", "coupler", "proto"},
    "launcher": {"launcher", "base", "coupler", "proto"},
}
GENERATED = {"proto/case.pb.h", "proto/coupling.pb.h"}  # written by protoc into the build tree
PUBLIC_COUPLER = "coupler/participant.hpp"
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]')


def main():
    root = sys.argv[1]
    problems, checked = [], 0
    for top in list(ALLOWED) + ["tests"]:
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".cpp", ".hpp", ".h")):
                    continue
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root)
                for number, line in enumerate(open(path, encoding="utf-8"), 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    kind, target = m.groups()
                    where = f"{rel}:{number}: {line.strip()}"
                    if rel == PUBLIC_COUPLER and (target.startswith("proto/") or "zmq" in target
                                                  or "google/protobuf" in target):
                        problems.append(f"{where}: the coupling library's public header must stay free of "
                                        "ZeroMQ and protobuf types")
                    if kind != '"':
                        continue
                    checked += 1
                    if "/" not in target:
                        problems.append(f"{where}: write includes from the repository root (folder/file)")
                        continue
                    if target not in GENERATED and not os.path.exists(os.path.join(root, target)):
                        problems.append(f"{where}: no such file in the repository")
                        continue
                    layer = target.split("/")[0]
                    if top != "tests" and layer not in ALLOWED[top]:
                        problems.append(f"{where}: {top}/ may include only "
                                        f"{', '.join(sorted(ALLOWED[top]))}, not {layer}/")
    for p in problems:
        print(p)
    print(f"check_layers: {checked} includes checked, {len(problems)} against the layers")
    sys.exit(1 if problems or checked == 0 else 0)


if __name__ == "__main__":
    main()
