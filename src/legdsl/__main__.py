"""``legdsl`` (the console script) and ``python -m legdsl``: the command line.

The command line's modules are imported here, inside ``main``, so that a Ctrl-C while
they load (the first second of a command) is told as one line, as later, not as a
traceback of the import.
"""

import sys


def main() -> int:
    try:
        from legdsl.cli import main as command_line
    except KeyboardInterrupt:
        print("legdsl: interrupted", file=sys.stderr)
        return 130  # legdsl.cli.common.EXIT_INTERRUPTED, which could not be imported
    except (MemoryError, SystemError):  # a memory limit (ulimit -v) too low to load numpy:
        # the import machinery then fails as SystemError ("... without setting an exception")
        print("legdsl: out of memory: raise the memory limit (ulimit -v)", file=sys.stderr)
        return 2
    return command_line()


if __name__ == "__main__":
    sys.exit(main())
