"""Runs the shell examples of the documentation that are marked runnable, against a built
astrojax, in a temporary folder: the guide must not show a command that fails.

A block is runnable when the line before its opening fence is an HTML comment at the start of
the line, starting with "runnable" (`<!-- runnable -->`), which the rendered page does not show. Blocks of one page run
in order, in one folder, so a later block may read what an earlier one wrote. The folder looks
like a checkout: build/astrojax is the astrojax under test, and sweeps/, analysis/ and
tests/data/ are the repository's (read only; outputs go to out/).

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
FENCE = re.compile(r"^```(\w*)")


def runnable_blocks(page):
    """(line number, code) of each marked shell block of a Markdown page."""
    lines = page.read_text().split("\n")
    blocks = []
    for i, line in enumerate(lines):
        if not MARK.match(line):  # at the start of the line: an indented one is an example
            continue
        fence = FENCE.match(lines[i + 1]) if i + 1 < len(lines) else None
        if not fence or fence.group(1) not in ("sh", "bash", "shell"):
            raise SystemExit(f"{page}:{i + 1}: a runnable mark must stand right above a ```sh block")
        end = next(j for j in range(i + 2, len(lines)) if lines[j].startswith("```"))
        blocks.append((i + 2, "\n".join(lines[i + 2:end])))
    return blocks


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
            for line, code in blocks:
                total += 1
                start = time.monotonic()
                r = subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=folder, env=env,
                                   capture_output=True, text=True, timeout=900)
                where = f"{page.relative_to(source)}:{line}"
                print(f"{where}: exit {r.returncode} in {time.monotonic() - start:.1f} s")
                if r.returncode != 0:
                    failed.append(f"{where}: exit {r.returncode}\n{code}\n--- stdout\n{r.stdout[-3000:]}"
                                  f"\n--- stderr\n{r.stderr[-3000:]}")
    for f in failed:
        print("FAILED", f, file=sys.stderr)
    print(f"{total} runnable blocks, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
