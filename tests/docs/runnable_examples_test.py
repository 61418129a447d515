"""Runs the shell examples of the documentation that are marked runnable, against a built
astrojax, in a temporary folder: the guide must not show a command that fails.

A block is runnable when the line before its opening fence is an HTML comment at the start of
the line, starting with "runnable" (`<!-- runnable -->`), which the rendered page does not show. Blocks of one page run
in order, in one folder, so a later block may read what an earlier one wrote. The folder looks
like a checkout: build/astrojax is the astrojax under test, and sweeps/, analysis/ and
tests/data/ are the repository's (read only; outputs go to out/).

A page may also show what a runnable block prints: a fenced block with the comment
`<!-- output -->` on the line above its opening fence belongs to the last runnable block above
it, and is compared with that block's stdout followed by its stderr:
- blank lines are ignored, and every other expected line must match one printed line, in the
  same order, with any printed lines in between (so a page may show only the key lines);
- within a line, runs of whitespace count as one space, leading and trailing space is ignored,
  and `…` stands for any text (a time, a path);
- numbers (optional sign, digits, optional fraction and exponent) are compared as numbers:
  |printed − expected| ≤ atol + rtol |expected|, by default rtol = 1e-6 and atol = 0, or as set
  in the mark: `<!-- output rtol=0.01 atol=1e-12 -->`.
A mismatch names the page, the line of the expected block and the first expected line not
found, and fails the test like a non-zero exit.

usage: runnable_examples_test.py ASTROJAX SOURCE_DIR PATH [PATH ...]
A PATH that is a page must have a runnable block; a folder stands for its pages that have one.
"""
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

MARK = re.compile(r"^<!--\s*runnable\b.*-->\s*$")
OUTPUT = re.compile(r"^<!--\s*output\b(.*)-->\s*$")
FENCE = re.compile(r"^```(\w*)")
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


class Block:
    """A runnable block: its first line, its code, and the outputs the page shows for it, each
    (first line, expected lines, rtol, atol)."""
    def __init__(self, line, code):
        self.line, self.code, self.outputs = line, code, []


def fenced(lines, i, page):
    """The lines of the fenced block whose opening fence is lines[i], and the closing index."""
    end = next((j for j in range(i + 1, len(lines)) if lines[j].startswith("```")), None)
    if end is None:
        raise SystemExit(f"{page}:{i + 1}: a fence that never closes")
    return lines[i + 1:end], end


def tolerances(text, where):
    """rtol and atol of an output mark's text (`rtol=X atol=Y`, either optional)."""
    tol = {"rtol": 1e-6, "atol": 0.0}
    for item in text.split():
        key, _, value = item.partition("=")
        if key not in tol:
            raise SystemExit(f"{where}: an output mark knows rtol= and atol=, not '{item}'")
        try:
            tol[key] = float(value)
        except ValueError:
            raise SystemExit(f"{where}: {key}={value!r} is not a number") from None
    return tol["rtol"], tol["atol"]


def runnable_blocks(page):
    """The marked shell blocks of a Markdown page, with the outputs shown for them."""
    lines = page.read_text().split("\n")
    blocks = []
    for i, line in enumerate(lines):
        out = OUTPUT.match(line)
        if out:  # at the start of the line, like the runnable mark
            if not blocks:
                raise SystemExit(f"{page}:{i + 1}: an output mark with no runnable block above it")
            if i + 1 >= len(lines) or not FENCE.match(lines[i + 1]):
                raise SystemExit(f"{page}:{i + 1}: an output mark must stand right above a fence")
            body, _ = fenced(lines, i + 1, page)
            blocks[-1].outputs.append((i + 2, body, *tolerances(out.group(1), f"{page}:{i + 1}")))
        if not MARK.match(line):  # at the start of the line: an indented one is an example
            continue
        fence = FENCE.match(lines[i + 1]) if i + 1 < len(lines) else None
        if not fence or fence.group(1) not in ("sh", "bash", "shell"):
            raise SystemExit(f"{page}:{i + 1}: a runnable mark must stand right above a ```sh block")
        body, _ = fenced(lines, i + 1, page)
        blocks.append(Block(i + 2, "\n".join(body)))
    return blocks


def normalised(line):
    return " ".join(line.split())


def line_pattern(expected):
    """A regex for a normalised printed line: the expected line's text literally (a space for any
    whitespace, `…` for any text), each of its numbers a captured number."""
    parts, pos = [], 0
    for m in re.finditer(NUMBER, expected):
        parts.append(re.escape(expected[pos:m.start()]))
        parts.append(f"({NUMBER})")
        pos = m.end()
    parts.append(re.escape(expected[pos:]))
    return re.compile("".join(parts).replace(re.escape("…"), ".*?").replace(re.escape(" "), " ") + "$")


def line_matches(expected, printed, rtol, atol):
    m = line_pattern(expected).match(printed)
    if not m:
        return False
    numbers = [float(x) for x in re.findall(NUMBER, expected)]
    return all(abs(float(p) - e) <= atol + rtol * abs(e) for p, e in zip(m.groups(), numbers))


def output_mismatch(expected_lines, printed_text, rtol, atol):
    """None when every non-blank expected line matches a printed line in order, else the first
    expected line not found (after the lines matched before it)."""
    printed = [normalised(p) for p in printed_text.split("\n") if p.strip()]
    k = 0
    for raw in expected_lines:
        want = normalised(raw)
        if not want:
            continue
        while k < len(printed) and not line_matches(want, printed[k], rtol, atol):
            k += 1
        if k == len(printed):
            return want
        k += 1
    return None


def checkout_like(folder, astrojax, source):
    (folder / "build").mkdir()
    (folder / "build" / "astrojax").symlink_to(astrojax)
    for sub in ("sweeps", "analysis"):
        (folder / sub).symlink_to(source / sub)
    (folder / "tests").mkdir()
    (folder / "tests" / "data").symlink_to(source / "tests" / "data")
    (folder / "out").mkdir()


def main():
    astrojax = pathlib.Path(sys.argv[1]).resolve()
    source = pathlib.Path(sys.argv[2]).resolve()
    pages = []
    for arg in sys.argv[3:]:
        path = source / arg
        pages += sorted(p for p in path.rglob("*.md") if runnable_blocks(p)) if path.is_dir() else [path]
    env = dict(os.environ, ASTROJAX=str(astrojax), MPLBACKEND="Agg")
    total, failed = 0, []
    for page in pages:
        blocks = runnable_blocks(page)
        if not blocks:
            failed.append(f"{page.relative_to(source)}: no block marked runnable")
            continue
        with tempfile.TemporaryDirectory(prefix="docs_examples_") as tmp:
            folder = pathlib.Path(tmp)
            checkout_like(folder, astrojax, source)
            for block in blocks:
                total += 1
                start = time.monotonic()
                r = subprocess.run(["bash", "-euo", "pipefail", "-c", block.code], cwd=folder, env=env,
                                   capture_output=True, text=True, timeout=900)
                where = f"{page.relative_to(source)}:{block.line}"
                print(f"{where}: exit {r.returncode} in {time.monotonic() - start:.1f} s"
                      + (f", {len(block.outputs)} output block(s) compared" if block.outputs else ""))
                if r.returncode != 0:
                    failed.append(f"{where}: exit {r.returncode}\n{block.code}\n--- stdout\n{r.stdout[-3000:]}"
                                  f"\n--- stderr\n{r.stderr[-3000:]}")
                    continue
                for out_line, expected, rtol, atol in block.outputs:
                    missing = output_mismatch(expected, r.stdout + "\n" + r.stderr, rtol, atol)
                    if missing is not None:
                        failed.append(f"{page.relative_to(source)}:{out_line}: output: no printed line matches "
                                      f"'{missing}' (rtol {rtol:g}, atol {atol:g})\n--- stdout\n{r.stdout[-3000:]}"
                                      f"\n--- stderr\n{r.stderr[-3000:]}")
    for f in failed:
        print("FAILED", f, file=sys.stderr)
    print(f"{total} runnable blocks, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
