#!/usr/bin/env python3
"""The layering check: every #include in src/ and include/nori/ names a header of the
file's own area or of an area below it, as src/CMakeLists.txt declares them.

    check_layers.py ROOT TABLE

ROOT is a source tree, TABLE the build's generated/layers.txt. Prints each violation as
"file:line: ..." and exits 1 when there is one; ctest runs it (layers.*)."""
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def read_table(path):
    depends, headers = {}, {}
    for line in Path(path).read_text().splitlines():
        words = line.split()
        if not words or words[0] != "area":
            continue
        name = words[1]
        split = words.index("headers")
        depends[name] = words[3:split]
        headers[name] = words[split + 1:]
    return depends, headers


def below(area, depends):
    """The area and every area it depends on, transitively."""
    allowed, queue = {area}, list(depends[area])
    while queue:
        other = queue.pop()
        if other not in allowed:
            allowed.add(other)
            queue.extend(depends[other])
    return allowed


def main(root, table):
    root = Path(root)
    depends, headers = read_table(table)
    problems = []
    owner = {}
    for header in sorted(p.name for p in (root / "include/nori").glob("*.h")):
        owners = [area for area in depends if header in headers[area]]
        if len(owners) != 1:
            problems.append(f"include/nori/{header}: belongs to {len(owners)} areas "
                            f"({', '.join(owners) or 'none'}); list it in the HEADERS of "
                            "exactly one nori_add_area in src/CMakeLists.txt")
        else:
            owner[header] = owners[0]

    def check(path, area):
        allowed = below(area, depends)
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            delimiter, name = match.groups()
            if name.startswith("nori/"):
                target = owner.get(name[len("nori/"):])
                if target is None:
                    if not (root / "include" / name).exists():
                        problems.append(f"{path.relative_to(root)}:{number}: <{name}> does "
                                        "not exist")
                    continue
            elif delimiter == '"' and "/" in name and name.split("/")[0] in depends:
                target = name.split("/")[0]  # a header beside the sources of an area
            else:
                continue  # the standard library, a third-party header, or a local one
            if target not in allowed:
                problems.append(
                    f"{path.relative_to(root)}:{number}: area '{area}' includes {name} of "
                    f"area '{target}', which is not below it (it may include: "
                    f"{', '.join(sorted(allowed))})")

    for header, area in owner.items():
        check(root / "include/nori" / header, area)
    for area in depends:
        for path in sorted((root / "src" / area).glob("*")):
            if path.suffix in (".cpp", ".h"):
                check(path, area)

    for problem in problems:
        print(problem)
    if problems:
        print(f"{len(problems)} layering violation(s): an area may include only the headers "
              "of the areas below it (src/CMakeLists.txt)")
        return 1
    print(f"layers: {len(depends)} areas, every include points down")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
