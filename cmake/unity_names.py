#!/usr/bin/env python3
"""Names that two test files both define inside an anonymous namespace.

A unity build (tests/CMakeLists.txt) compiles several test files as one translation unit, and
which files share one changes with their sizes: two files that define the same helper in their
anonymous namespaces then stop compiling together. This lists every such name (a file's helpers
belong in a namespace named after it, e.g. `namespace glove_tests { ... }`). The parse is lexical:
comments, strings and preprocessor lines are dropped, braces are tracked, and the name of each
declaration whose enclosing scopes are all namespaces, one of them anonymous, is collected.

Usage: unity_names.py FILE...   (exit status 1 and one line per name when any is shared)
"""
import re
import sys
from collections import defaultdict

TOKENS = re.compile(r'//[^\n]*|/\*.*?\*/|R"(?P<d>[^(]*)\(.*?\)(?P=d)"|"(?:\\.|[^"\\\n])*"|'
                    r"'(?:\\.|[^'\\\n])*'|^[ \t]*#[^\n]*(?:\\\n[^\n]*)*", re.S | re.M)
KEYWORDS = {"const", "constexpr", "static", "inline", "struct", "class", "enum", "union", "typename",
            "template", "operator", "unsigned", "signed", "long", "short", "int", "double", "float",
            "bool", "char", "void", "auto", "noexcept", "override", "final", "volatile", "decltype"}


def strip(text):
    return TOKENS.sub(lambda m: '""' if m.group(0).startswith(('"', "R")) else " ", text)


def declared_name(head):
    """The name a namespace-scope declaration's head (its text up to '{' or ';') declares, and
    for an alias its text (None otherwise), or None."""
    head = head.strip()
    while head.startswith("template"):  # drop template <...>, nested brackets included
        depth, i = 0, head.index("<")
        for i in range(head.index("<"), len(head)):
            depth += {"<": 1, ">": -1}.get(head[i], 0)
            if depth == 0:
                break
        head = head[i + 1:].strip()
    if not head or re.match(r"(TEST_CASE|SCENARIO|SUBCASE|TYPE_TO_STRING|namespace\b|using namespace\b|"
                            r"static_assert\b|extern\b)", head):
        return None
    m = re.match(r"(?:enum\s+(?:class\s+|struct\s+)?|struct\s+|class\s+|union\s+)(\w+)", head)
    if m:
        return m.group(1), None
    if re.match(r"using\s+[\w:]+$", head):  # a using-declaration may be repeated
        return None
    m = re.match(r"using\s+(\w+)\s*=", head)
    if m:  # an alias may be repeated with the same type: its text is its identity
        return m.group(1), " ".join(head.split())
    cut = re.split(r"[(=\[{;]", head, maxsplit=1)[0]  # a function's or a variable's name ends here
    names = [w for w in re.findall(r"[A-Za-z_]\w*", cut) if w not in KEYWORDS]
    return (names[-1], None) if names else None


def qualified(scopes, name):
    """(scope::name, alias text): the same name in a named namespace of two files is one entity."""
    return "::".join([s[3:] if s != "anon" else "(anonymous)" for s in scopes] + [name[0]]), name[1]


def anonymous_names(text):
    text = strip(text)
    scopes = []  # per open brace: "anon", "ns:<name>" or "code"
    names, head = set(), ""
    for ch in text:
        at_namespace_scope = all(s != "code" for s in scopes)
        if ch == "{":
            kind = "code"
            if at_namespace_scope:
                m = re.search(r"namespace\s*(\w*)\s*$", head)
                if m:
                    kind = "ns:" + m.group(1) if m.group(1) else "anon"
                elif "anon" in scopes:
                    name = declared_name(head)
                    if name:
                        names.add(qualified(scopes, name))
                head = ""
            scopes.append(kind)
        elif ch == "}":
            if scopes:
                scopes.pop()
            if all(s != "code" for s in scopes):
                head = ""
        elif ch == ";" and at_namespace_scope:
            if "anon" in scopes:
                name = declared_name(head)
                if name:
                    names.add(qualified(scopes, name))
            head = ""
        elif at_namespace_scope:
            head += ch
    return names


def main(paths):
    owners = defaultdict(list)
    for path in paths:
        with open(path, encoding="utf-8") as f:
            for name, alias in anonymous_names(f.read()):
                owners[name].append((path, alias))
    shared = {}
    for name, defs in owners.items():
        paths = sorted({p for p, _ in defs})
        aliases = {a for _, a in defs}
        if len(paths) > 1 and not (len(aliases) == 1 and None not in aliases):
            shared[name] = paths
    if shared:
        print("defined in anonymous namespaces of several test files (a unity build may compile them")
        print("together; put each file's helpers in a namespace named after it):")
    for name in sorted(shared):
        print(f"{name}: {' '.join(shared[name])}")
    return 1 if shared else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
