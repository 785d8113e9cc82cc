#!/usr/bin/env python3
"""The repository needs nothing beside it: no tracked file names a path that
leaves the checkout (a sibling folder such as ../shared, a parent of the
source root). .ci/run proves the same by testing a clone alone in a new
temporary folder; this test names the offending file and line at once.

Usage: self_contained_test.py SOURCE_DIR
"""
import pathlib
import re
import subprocess
import sys

# A path that climbs out of the source root: the source root's parent in
# CMake or C++ ("${PROJECT_SOURCE_DIR}/..", HAPTICBENCH_SOURCE_DIR) / ".."),
# or a sibling folder of the checkout named from a script or a document.
LEAVING = [
    re.compile(r"SOURCE_DIR\}?/\.\.(?:/|\"|$)"),
    re.compile(r"SOURCE_DIR\)?\s*/\s*\"\.\./"),
    re.compile(r"(?<![\w.])\.\./shared\b"),
]
# This file names the patterns it looks for.
SELF = "tests/repository/self_contained_test.py"


def main() -> int:
    root = pathlib.Path(sys.argv[1]).resolve()
    listed = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], check=True,
                            capture_output=True).stdout.split(b"\0")
    files = [name.decode() for name in listed if name]
    if not files:
        print(f"self_contained_test: git lists no files under {root}")
        return 1
    found = []
    for name in files:
        if name == SELF:
            continue
        path = root / name
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue  # binary data, or a file deleted in the working tree
        for number, line in enumerate(text.splitlines(), 1):
            if any(p.search(line) for p in LEAVING):
                found.append(f"{name}:{number}: {line.strip()}")
    for line in found:
        print("reads outside the repository:", line)
    print(f"self_contained_test: {len(files)} tracked files, {len(found)} paths outside")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
