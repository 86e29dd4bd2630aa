#!/usr/bin/env python3
"""readme_snippet.py [README.md [ROOT]]

The README shows source code as a fenced block right after a line
`<!-- snippet: PATH -->` (PATH from ROOT, the checkout). Each such block's
lines must appear in PATH contiguously and verbatim, so that what a reader
sees is code that builds and that the tests run. Exits 1, naming the file
and the first line that differs, when one does not.

With no arguments it checks README.md in the checkout this script is in.
"""
import os
import re
import sys

MARKER = re.compile(r"^<!-- snippet: (\S+) -->\s*$")
FENCE = re.compile(r"^(```+|~~~+)")


def snippets(lines):
    """Yield (path, marker line number, first block line number, block lines)."""
    i = 0
    while i < len(lines):
        m = MARKER.match(lines[i])
        if not m:
            i += 1
            continue
        path, marker_line = m.group(1), i + 1
        i += 1
        while i < len(lines) and not lines[i].strip():
            i += 1
        opening = FENCE.match(lines[i]) if i < len(lines) else None
        if not opening:
            yield path, marker_line, None, None
            continue
        fence = opening.group(1)
        i += 1
        start = i
        while i < len(lines) and not lines[i].startswith(fence):
            i += 1
        if i == len(lines):
            yield path, marker_line, start + 1, None
            continue
        yield path, marker_line, start + 1, lines[start:i]
        i += 1


def first_difference(block, source):
    """Where the block comes nearest to matching the source: the index of the
    block's first line that differs, and the source line found there (or None)."""
    best_k, best_at = -1, None
    for at in range(len(source)):
        k = 0
        while k < len(block) and at + k < len(source) and source[at + k] == block[k]:
            k += 1
        if k > best_k:
            best_k, best_at = k, at
    if best_k <= 0:
        return 0, None
    found = source[best_at + best_k] if best_at + best_k < len(source) else None
    return best_k, found


def check(readme, root):
    with open(readme, encoding="utf-8") as f:
        lines = f.read().split("\n")
    count = 0
    for path, marker_line, first_line, block in snippets(lines):
        where = f"{readme}:{marker_line}"
        if first_line is None:
            return f"{where}: the snippet marker for {path} is not followed by a fenced code block"
        if block is None:
            return f"{where}: the code block for {path} is not closed"
        if not block:
            return f"{where}: the code block for {path} is empty"
        full = os.path.join(root, path)
        if not os.path.isfile(full):
            return f"{where}: {path} does not exist (looked for {full})"
        with open(full, encoding="utf-8") as f:
            source = f.read().split("\n")
        n = len(block)
        if any(source[at:at + n] == block for at in range(len(source) - n + 1)):
            count += 1
            continue
        k, found = first_difference(block, source)
        message = (f"{where}: the README's code block is not a contiguous, verbatim part of {path}.\n"
                   f"First differing line, {readme}:{first_line + k}:\n"
                   f"  README: {block[k]!r}\n")
        if k == 0:
            message += f"  {path}: no line of it starts the block as the README does"
        elif found is None:
            message += f"  {path}: ends after the {k} line(s) that match"
        else:
            message += f"  {path}: {found!r} (after {k} matching line(s))"
        return message
    if count == 0:
        return f"{readme}: no '<!-- snippet: PATH -->' marker"
    print(f"{readme}: {count} snippet(s) match their files")
    return None


def main(argv):
    here = os.path.dirname(os.path.abspath(__file__))
    root_default = os.path.dirname(here)
    if len(argv) > 3 or (len(argv) > 1 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    readme = argv[1] if len(argv) > 1 else os.path.join(root_default, "README.md")
    root = argv[2] if len(argv) > 2 else os.path.dirname(os.path.abspath(readme))
    error = check(readme, root)
    if error:
        print(error, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
