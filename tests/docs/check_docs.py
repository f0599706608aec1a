#!/usr/bin/env python3
"""Keeps the documentation honest. Three checks, each a ctest test (docs.*):

    check_docs.py links ROOT            the README links every document of docs/ and
                                        CONTRIBUTING.md, and every relative link of them
                                        names a file that exists
    check_docs.py plugins ROOT NORI     the README's plugin table names exactly the plugins
                                        that `nori --list-plugins` lists
    check_docs.py commands ROOT BUILD WORK
                                        every ```sh block of the README, CONTRIBUTING.md and
                                        docs/ runs as written and exits 0, in WORK (a copy of
                                        scenes/ and scripts/, with `build` pointing at BUILD),
                                        unless the line before it is <!-- not run: REASON -->

Exits 1 with a line per problem."""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

BLOCK = re.compile(r"(?P<before>[^\n]*)\n```(?P<lang>\w*)\n(?P<body>.*?)```", re.S)
NOT_RUN = re.compile(r"<!-- not run: .+ -->")
# A command may take this long; the slowest renders the Cornell box at 64 spp. The
# sanitizer build, several times slower, scales it (NORI_TIMEOUT_FACTOR, set by ctest).
TIMEOUT_SECONDS = 300 * int(os.environ.get("NORI_TIMEOUT_FACTOR", "1"))


def documents(root):
    files = sorted((root / "docs").rglob("*.md"))
    return [root / "README.md", root / "CONTRIBUTING.md"] + files


def check_links(root):
    readme = (root / "README.md").read_text()
    linked = set()
    for target in re.findall(r"\]\(([^)#\s]+)", readme):
        if "://" not in target:
            linked.add((root / target).resolve())
    problems = []
    for path in documents(root)[1:]:
        if path.resolve() not in linked:
            problems.append(f"README.md does not link {path.relative_to(root)}")
    for path in documents(root):
        for target in re.findall(r"\]\(([^)#\s]+)", path.read_text()):
            if "://" not in target and not (path.parent / target).exists():
                problems.append(f"{path.relative_to(root)} links {target}, which does not exist")
    return problems


def check_plugins(root, nori):
    readme = (root / "README.md").read_text()
    begin, end = "<!-- plugins: begin -->", "<!-- plugins: end -->"
    if begin not in readme or end not in readme:
        return [f"README.md has no plugin table between {begin} and {end}"]
    table = readme[readme.index(begin):readme.index(end)]
    documented = {}
    for line in table.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) == 2 and cells[0] not in ("kind", "---"):
            documented[cells[0]] = set(re.findall(r"`([^`]+)`", cells[1]))
    listing = subprocess.run([nori, "--list-plugins"], capture_output=True, text=True,
                             check=True).stdout
    registered, kind = {}, None
    for line in listing.splitlines():
        if re.fullmatch(r"[a-z]+:", line):
            kind = line[:-1]
            registered[kind] = set()
        elif line.startswith("  ") and kind:
            registered[kind].add(line.split()[0])
    registered.pop("scene", None)  # the root object, not a plugin one chooses
    # A plugin from a file that is not the project's own (plugins/builtin/shipped.txt: a
    # user's file dropped into plugins/course/) is not in the table, and need not be.
    shipped = {"plugins/builtin/" + line.strip() for line in
               (root / "plugins" / "builtin" / "shipped.txt").read_text().splitlines()
               if line.strip() and not line.startswith("#")}

    def is_shipped(name):
        reference = subprocess.run([nori, "--list-plugins", name], capture_output=True,
                                   text=True, check=True).stdout
        match = re.search(r"\(\w+, ([^)]+)\)", reference)
        return match is not None and match.group(1) in shipped

    problems = []
    for kind in sorted(set(documented) | set(registered)):
        missing = {name for name in registered.get(kind, set()) - documented.get(kind, set())
                   if is_shipped(name)}
        extra = documented.get(kind, set()) - registered.get(kind, set())
        if missing:
            problems.append(f"README.md's plugin table lacks {kind}: {', '.join(sorted(missing))}")
        if extra:
            problems.append(f"README.md's plugin table names {kind} plugins that do not exist: "
                            f"{', '.join(sorted(extra))}")
    return problems


def check_commands(root, build, work):
    work = Path(work)
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    for folder in ("scenes", "scripts", "blender"):
        shutil.copytree(root / folder, work / folder, symlinks=True)
    (work / "build").symlink_to(Path(build).resolve())
    problems, ran, skipped = [], 0, 0
    for path in documents(root):
        text = path.read_text()
        for match in BLOCK.finditer(text):
            if match.group("lang") not in ("sh", "bash"):
                continue
            line = text[:match.start("body")].count("\n")
            where = f"{path.relative_to(root)}:{line}"
            if NOT_RUN.search(match.group("before")):
                skipped += 1
                continue
            body = match.group("body")
            print(f"--- {where}\n{body}", flush=True)
            try:
                result = subprocess.run(["bash", "-euo", "pipefail", "-c", body], cwd=work,
                                        capture_output=True, text=True, timeout=TIMEOUT_SECONDS,
                                        env=dict(os.environ, NORI_DOC_TEST="1"))
            except subprocess.TimeoutExpired:
                problems.append(f"{where}: the block did not finish in {TIMEOUT_SECONDS} s")
                continue
            ran += 1
            if result.returncode != 0:
                tail = (result.stdout + result.stderr).strip().splitlines()[-5:]
                problems.append(f"{where}: the block exited {result.returncode}:\n    " +
                                "\n    ".join(tail))
    print(f"{ran} blocks ran, {skipped} marked not run")
    return problems


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    mode, root = argv[1], Path(argv[2]).resolve()
    if mode == "links" and len(argv) == 3:
        problems = check_links(root)
    elif mode == "plugins" and len(argv) == 4:
        problems = check_plugins(root, argv[3])
    elif mode == "commands" and len(argv) == 5:
        problems = check_commands(root, argv[3], argv[4])
    else:
        sys.exit(__doc__)
    for problem in problems:
        print(problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
