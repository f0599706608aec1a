#!/usr/bin/env python3
"""The layering check: every #include in src/ and include/nori/ names a header of the
file's own area or of an area below it, as src/CMakeLists.txt declares them; and no
area's library uses a symbol that only an area above it defines.

    check_layers.py ROOT TABLE                 the includes of the source tree ROOT
    check_layers.py --symbols LIBDIR TABLE     the libraries libnori_AREA.a in LIBDIR

TABLE is the build's generated/layers.txt. Prints each violation and exits 1 when there
is one; ctest runs both (layers.*)."""
import re
import subprocess
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


def check_symbols(libdir, table):
    """Undefined symbols of each area's library that only libraries of areas not below it
    define (inline functions and templates, defined weakly wherever they are used, count
    as defined by the user's own areas)."""
    depends, _ = read_table(table)
    defined, undefined = {}, {}
    for area in depends:
        listing = subprocess.run(["nm", "-g", str(Path(libdir) / f"libnori_{area}.a")],
                                 capture_output=True, text=True, check=True).stdout
        defined[area], undefined[area] = set(), set()
        for line in listing.splitlines():
            fields = line.split()
            if len(fields) == 2 and fields[0] == "U":
                undefined[area].add(fields[1])
            elif len(fields) == 3 and fields[1] in "TDBRVWu":
                defined[area].add(fields[2])
    problems = []
    for area in depends:
        allowed = below(area, depends)
        mine = set().union(*(defined[other] for other in allowed))
        for other in depends:
            if other in allowed:
                continue
            used = sorted((undefined[area] & defined[other]) - mine)
            if used:
                names = subprocess.run(["c++filt"] + used[:3], capture_output=True,
                                       text=True).stdout.split("\n")
                problems.append(f"libnori_{area}.a uses {len(used)} symbol(s) of area "
                                f"'{other}', which is not below it, e.g. {names[0]}")
    for problem in problems:
        print(problem)
    if problems:
        return 1
    print(f"layers: {len(depends)} libraries, every symbol they use is defined below them")
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0)
    if len(sys.argv) == 4 and sys.argv[1] == "--symbols":
        sys.exit(check_symbols(sys.argv[2], sys.argv[3]))
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2]))
