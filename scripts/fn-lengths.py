#!/usr/bin/env python3
"""Functions longer than LIMIT lines (from the `fn` line to its closing brace at the same indent).

Usage: scripts/fn-lengths.py LIMIT FILE...   e.g. scripts/fn-lengths.py 100 $(find crates/fairway-editor/src -name '*.rs')
"""
import re
import sys

limit = int(sys.argv[1])
for path in sys.argv[2:]:
    lines = open(path).read().split("\n")
    for i, line in enumerate(lines):
        m = re.match(r"^(\s*)(pub(\([a-z]+\))? )?(const )?fn \w+", line)
        if not m or line.rstrip().endswith(";"):
            continue  # not a fn, or a declaration without a body
        indent = m.group(1)
        end = next((j for j in range(i, len(lines)) if lines[j].startswith(indent + "}")), len(lines) - 1)
        if end - i + 1 > limit:
            print(f"{path}:{i + 1}: {end - i + 1} lines: {line.strip()[:70]}")
