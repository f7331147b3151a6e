#!/usr/bin/env python3
"""Lists the functions of include/grip that the coverage run never executed.

Reads `llvm-cov export` JSON on stdin. A function template has one record per instantiation;
a function counts as executed when any record that starts at the same place (file, line) ran.
A template that nothing instantiates has no record at all and is not listed here.

Prints "include/grip/<file>:<line>: <source line>" per unexecuted function, sorted, and the
count last. Exit status 0 always; cmake/coverage.sh decides what to do with the count.
"""
import json
import os
import sys


def main():
    data = json.load(sys.stdin)["data"]
    ran = {}
    for export in data:
        for fn in export.get("functions", []):
            regions = fn.get("regions") or []
            files = fn.get("filenames") or []
            if not regions or not files:
                continue
            path = files[regions[0][5]] if regions[0][5] < len(files) else files[0]
            marker = os.sep + "include" + os.sep + "grip" + os.sep
            if marker not in path:
                continue
            key = (path[path.index(marker) + 1:], regions[0][0])
            ran[key] = ran.get(key, False) or fn.get("count", 0) > 0
    missed = sorted(k for k, v in ran.items() if not v)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for path, line in missed:
        text = ""
        try:
            with open(os.path.join(root, path)) as f:
                text = f.read().splitlines()[line - 1].strip()
        except (OSError, IndexError):
            pass
        print(f"{path}:{line}: {text}")
    print(f"{len(missed)} of {len(ran)} functions of include/grip never executed")


if __name__ == "__main__":
    main()
