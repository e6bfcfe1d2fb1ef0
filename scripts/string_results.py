#!/usr/bin/env python3
"""Counts the `Result<T, String>` types written in the workspace's Rust files (library and test
code, build output left out), nested generics included (`Result<Vec<f64>, String>`, which a
one-line grep misses), per file: `python3 scripts/string_results.py [ROOT]`."""

import os
import re
import sys


def split_top_level(inner):
    """The comma-separated arguments of a generic list, at depth 0."""
    parts, depth, current = [], 0, ""
    for c in inner:
        if c in "<([":
            depth += 1
        elif c in ">)]":
            depth -= 1
        if c == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += c
    parts.append(current)
    return parts


def count(text):
    found = 0
    for m in re.finditer(r"\bResult\s*<", text):
        i = j = m.end()
        depth = 1
        while j < len(text) and depth > 0:
            if text[j] == "<":
                depth += 1
            elif text[j] == ">" and text[j - 1] != "-":
                depth -= 1
            j += 1
        parts = split_top_level(text[i:j - 1])
        if len(parts) == 2 and parts[1].strip() == "String":
            found += 1
    return found


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    total, per_file = 0, []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if d not in {"target", ".git"})
        for f in sorted(filenames):
            if f.endswith(".rs"):
                path = os.path.join(dirpath, f)
                n = count(open(path, encoding="utf-8").read())
                if n:
                    per_file.append((n, path))
                    total += n
    for n, path in sorted(per_file, reverse=True):
        print(f"{n:4d}  {path}")
    print(f"{total} Result<_, String> type(s)")


if __name__ == "__main__":
    main()
