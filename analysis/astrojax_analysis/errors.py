"""The one error of a damaged or unsuitable file, and how every script ends on bad input.

`SweepFileError` is raised by the reader (reader.py) for a sweep or run file that fails a
check: missing, not HDF5, a newer format, a dataset absent, of the wrong rank, shape or type,
a checksum failure, a value the writer never stores. Scripts do not catch it themselves:
`cli.run(main)` turns it into `error: <path>: <dataset>: <message>` on stderr and exit 2.
"""
import sys

from .labels import printable


class SweepFileError(Exception):
    """A sweep or run file the reader refuses. Attributes: `path` (the file), `dataset` (the
    HDF5 path inside it, e.g. '/windows/class', '/' for the root; None for the file as a
    whole) and `message` (what is wrong, with the allowed range where there is one)."""

    def __init__(self, path, dataset, message):
        self.path, self.dataset, self.message = str(path), dataset, message
        where = f"{self.path}: {dataset}" if dataset else self.path
        super().__init__(f"{printable(where)}: {printable(message)}")


def fail(message):
    """Stop a script with a message on stderr and exit code 2 (bad input), like astrojax."""
    print(f"error: {printable(message)}", file=sys.stderr)
    sys.exit(2)
