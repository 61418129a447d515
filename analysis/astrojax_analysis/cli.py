"""Command-line plumbing shared by the scripts: the argument parser and `run`, which ends a
script on bad input with one line `error: ...` on stderr and exit code 2, never a traceback."""
import argparse
import math
import sys

from .errors import SweepFileError, fail
from .labels import printable


class Parser(argparse.ArgumentParser):
    """argparse with its description as written and its errors as one line, exit 2."""

    def __init__(self, doc=None, **kw):
        kw.setdefault("formatter_class", argparse.RawDescriptionHelpFormatter)
        super().__init__(description=doc if doc is not None else kw.pop("description", None), **kw)

    def error(self, message):
        fail(f"{message} (see {self.prog} --help)")


def parser(doc):
    """An argparse parser whose description is the script's docstring (--help shows usage)."""
    return Parser(doc)


def float_list(text, option):
    """A comma-separated list of finite numbers given to `option`."""
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        fail(f"{option}: '{text}' is not a comma-separated list of numbers")
    if not all(math.isfinite(v) for v in values):
        fail(f"{option}: '{text}': the numbers must be finite")
    return values


def run(main, argv=None):
    """Runs a script's main(argv): a SweepFileError, an unreadable file or a file that is not
    there becomes `error: ...` on stderr and exit 2. Returns main's value (exit 0)."""
    try:
        return main(argv)
    except SweepFileError as e:
        print(f"error: {e}", file=sys.stderr)
    except (OSError, UnicodeDecodeError) as e:  # a file missing, unreadable or not text
        name = getattr(e, "filename", None)
        reason = getattr(e, "strerror", None) or str(e)
        print(f"error: {printable(name) + ': ' if name else ''}{printable(reason)}", file=sys.stderr)
    sys.exit(2)
