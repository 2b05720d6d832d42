#!/usr/bin/env python3
"""The layer table holds: every folder of src/tc/ (and apps/thermocontact/) is a CMake target
whose links are those of its row in docs/architecture.md's "Allowed dependencies" table, and
every `#include "tc/..."` of its files names a folder it may use (itself, or a target its row
reaches through the table). Exit 1 with each violation listed; ctest runs it (label unit).

usage: check_layers.py SOURCE_DIR
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
errors = []


def table():
    """target -> the tc targets its row links (the other entries, packages, are not checked)."""
    text = (root / "docs/architecture.md").read_text()
    section = text.split("## Allowed dependencies", 1)
    if len(section) < 2:
        sys.exit("docs/architecture.md has no '## Allowed dependencies' section")
    rows = {}
    for line in section[1].splitlines():
        if line.startswith("## "):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not re.fullmatch(r"`?(tc_\w+|thermocontact)`?", cells[0]):
            continue
        target = cells[0].strip("`")
        if target in rows:
            errors.append(f"architecture.md: {target} has two rows")
        rows[target] = set(re.findall(r"\btc_\w+", cells[1]))
    return rows


def folders():
    """target -> folder, for every folder with sources (src/tc/a/b -> tc_a_b)."""
    found = {"thermocontact": root / "apps/thermocontact"}
    for d in sorted((root / "src/tc").rglob("*")):
        if d.is_dir() and any(f.suffix in (".hpp", ".cpp") for f in d.iterdir()):
            found["tc_" + "_".join(d.relative_to(root / "src/tc").parts)] = d
    return found


rows = table()
dirs = folders()

for target in sorted(set(dirs) - set(rows)):
    errors.append(f"{dirs[target].relative_to(root)}: no row {target} in architecture.md")
for target in sorted(set(rows) - set(dirs)):
    errors.append(f"architecture.md: row {target} has no folder with sources")
for target, links in rows.items():
    for t in sorted(links - set(rows)):
        errors.append(f"architecture.md: {target} links {t}, which has no row")


def reach(target, seen=None):
    seen = set() if seen is None else seen
    for t in rows.get(target, ()):
        if t not in seen:
            seen.add(t)
            reach(t, seen)
    return seen


for target in rows:
    if target in reach(target):
        errors.append(f"architecture.md: {target} reaches itself (a cycle)")

# The CMake target of each folder links exactly the tc targets of its row.
for target, d in dirs.items():
    if target not in rows or target == "thermocontact":
        continue
    cmake = d / "CMakeLists.txt"
    m = re.search(r"tc_layer\(\s*(\w+)([^)]*)\)", cmake.read_text()) if cmake.exists() else None
    if not m:
        errors.append(f"{d.relative_to(root)}: no tc_layer(...) in CMakeLists.txt")
        continue
    if "tc_" + m.group(1) != target:
        errors.append(f"{cmake.relative_to(root)}: target tc_{m.group(1)}, folder says {target}")
    links = set(re.findall(r"\btc_\w+", m.group(2)))
    if links != rows[target]:
        errors.append(f"{cmake.relative_to(root)}: links {sorted(links)}, "
                      f"architecture.md says {sorted(rows[target])}")

# Every include of a folder's files is of a folder its target may use.
by_path = {d.relative_to(root / "src").as_posix(): t for t, d in dirs.items() if t != "thermocontact"}
include = re.compile(r'^\s*#\s*include\s*"(tc/[^"]+)/[^/"]+"', re.M)
for target, d in dirs.items():
    allowed = reach(target) | {target}
    for f in sorted(d.iterdir()):
        if f.suffix not in (".hpp", ".cpp"):
            continue
        for folder in include.findall(f.read_text()):
            used = by_path.get(folder)
            if used is None:
                errors.append(f"{f.relative_to(root)}: includes from {folder}/, not a layer")
            elif used not in allowed:
                errors.append(f"{f.relative_to(root)}: includes {folder}/ ({used}), which "
                              f"{target} may not use (docs/architecture.md)")

for e in errors:
    print(e)
if errors:
    sys.exit(1)
print(f"{len(dirs)} layers, their links and their includes agree with docs/architecture.md")
