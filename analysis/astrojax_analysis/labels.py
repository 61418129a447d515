"""Text from a file, made safe to print or draw: labels and purposes may hold any UTF-8
(FORMAT 3), so a newline, a NUL or an ANSI escape is shown escaped and a 10 kB label is cut
to a length that a terminal line or a figure's raster holds."""

TERMINAL_LIMIT = 200   # characters of one label on a terminal line
FIGURE_LIMIT = 120     # characters of one label in a title or legend entry (the shipped ones: up to 66)


def _escape(ch):
    if ch == "\t":
        return " "
    if ch.isprintable() or ch == " ":
        return ch
    if ch in "\n\r":
        return "\\n" if ch == "\n" else "\\r"
    code = ord(ch)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def ellipsize(text, limit):
    """`text` cut to at most `limit` characters, with '…' where it was cut."""
    return text if limit is None or len(text) <= limit else text[:max(limit - 1, 0)] + "…"


def printable(text, limit=None):
    """`text` (str or bytes) with every non-printable character escaped (\\n, \\x00, \\x1b ...),
    then cut to `limit` characters."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", "backslashreplace")
    return ellipsize("".join(_escape(ch) for ch in str(text)), limit)


def for_figure(text, limit=FIGURE_LIMIT):
    """A label to draw with matplotlib: escaped, cut, and with '$' escaped so that it is
    never read as mathtext."""
    return printable(text, limit).replace("$", r"\$")
