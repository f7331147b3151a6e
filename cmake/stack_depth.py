#!/usr/bin/env python3
"""Worst-case stack depth from GCC's -fcallgraph-info=su output (a .ci file, VCG format).

Usage: stack_depth.py FILE.ci ROOT_SYMBOL
Prints "<bytes> <path>" for the deepest call chain from ROOT_SYMBOL (static frames summed);
prints "unbounded ..." and exits 1 on recursion or a dynamically sized frame. Calls to
functions outside the file (e.g. sqrtf in libm) count 0 bytes and are listed as external.
"""
import re
import sys

def main():
    text = open(sys.argv[1]).read()
    root = sys.argv[2]
    frames, names, edges = {}, {}, {}
    for m in re.finditer(r'node: \{ title: "([^"]*)" label: "((?:[^"\\]|\\.)*)"', text):
        title, label = m.group(1), m.group(2)
        size = re.search(r'\\n(\d+) bytes \((static|dynamic[^)]*)\)', label)
        frames[title] = (int(size.group(1)), size.group(2)) if size else None
        names[title] = label.split('\\n')[0]
    for m in re.finditer(r'edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"', text):
        edges.setdefault(m.group(1), set()).add(m.group(2))
    roots = [t for t in frames if t.endswith(':' + root) or t == root]
    if not roots:
        print('root %s not found' % root)
        return 1
    memo, external, bad = {}, set(), []

    def depth(t, stack):
        if t in stack:
            bad.append('recursion through ' + names.get(t, t))
            return 0, []
        if t in memo:
            return memo[t]
        f = frames.get(t)
        if f is None:
            external.add(t.split(':')[-1])
            return 0, [t.split(':')[-1]]
        if f[1] != 'static':
            bad.append('%s frame in %s' % (f[1], names[t]))
        best, path = 0, []
        for u in edges.get(t, ()):
            d, p = depth(u, stack | {t})
            if d > best:
                best, path = d, p
        memo[t] = (f[0] + best, [names[t]] + path)
        return memo[t]

    total, path = depth(roots[0], frozenset())
    print('%d bytes worst-case stack from %s' % (total, root))
    for p in path:
        print('    ' + p[:140])
    if external:
        print('  external calls (0 bytes counted): ' + ' '.join(sorted(external)))
    if bad:
        print('unbounded: ' + '; '.join(bad))
        return 1
    return 0

if __name__ == '__main__':
    sys.exit(main())
