# The --help of the Python scripts under scripts/ that run inside Blender (or import a
# module that needs it): the comment block at the top of a script is its help, printed
# without Blender. tests/scripts/help.sh runs every script with --help.
import sys


def exit_with_help(path, always=False):
    """Prints the comment block at the top of `path`, without its '# ', and exits with
    status 0, when the script's first argument is -h or --help (or `always`)."""
    if not always and sys.argv[1:2] not in (["-h"], ["--help"]):
        return
    with open(path) as source:
        for line in source:
            if not line.startswith("#"):
                break
            print(line[2:].rstrip())
    sys.exit(0)


if __name__ == "__main__":
    exit_with_help(__file__, always=True)
