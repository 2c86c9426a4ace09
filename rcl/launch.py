"""The `rcl` command's start: a Ctrl-C while it imports (numpy, the parser) ends it as a Ctrl-C
anywhere else before a program runs does, with a message and exit status 130, not a traceback."""
from __future__ import annotations

import sys

EXIT_INTERRUPTED = 130  # as rcl.errors has it (not imported here: the point is to import little first)


def main() -> None:
    """Console-script entry point: rcl.cli.entry, once imported."""
    try:
        from .cli import entry

        entry()  # (it takes a Ctrl-C while a program runs itself, and halts the robot first)
    except KeyboardInterrupt:  # while importing, or reading the command line
        sys.stderr.write("rcl: interrupted (Ctrl-C)\n")
        sys.exit(EXIT_INTERRUPTED)
