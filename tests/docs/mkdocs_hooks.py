"""MkDocs hooks (mkdocs.yml `hooks:`, MkDocs >= 1.4).

Before every build (`mkdocs build`, each rebuild of `mkdocs serve`, ./setup.sh docs): the
generated pages and figures written from the built program by tests/docs/generate_pages.sh:
the one named by the environment variable ASTROJAX, else build/astrojax (./setup.sh build).
After it: Debian's MathJax (libjs-mathjax) linked into the site, not copied (41 MB).

While reading the pages: lets them keep the list style GitHub renders (a list right under its
lead-in line, sub-items indented by two spaces), which Python-Markdown would otherwise run into
the paragraph above or flatten. At build time it inserts the blank line before a list and
doubles a two-space sub-item indent to the four spaces Python-Markdown nests by."""
import os
import pathlib
import re
import subprocess

from mkdocs.exceptions import PluginError

MATHJAX = pathlib.Path("/usr/share/javascript/mathjax")

LIST_ITEM = re.compile(r"^( *)([-*+]|\d+\.) ")


def normalise_lists(markdown):
    out, fence, prev = [], False, ""
    for line in markdown.split("\n"):
        if line.lstrip().startswith("```"):
            fence = not fence
        elif not fence:
            m = LIST_ITEM.match(line)
            if m:
                indent = len(m.group(1))
                if 0 < indent < 4:
                    line = " " * (2 * indent) + line[indent:]
                lead_in = prev.strip() and not prev.startswith(" ") and not LIST_ITEM.match(prev)
                if lead_in and not prev.lstrip().startswith(("|", "<!--")):
                    out.append("")
        out.append(line)
        prev = line
    return "\n".join(out)


def on_page_markdown(markdown, **kwargs):
    return normalise_lists(markdown)


def on_pre_build(config, **kwargs):
    root = pathlib.Path(config.config_file_path).resolve().parent
    binary = pathlib.Path(os.environ.get("ASTROJAX") or root / "build" / "astrojax")
    if not os.access(binary, os.X_OK):
        raise PluginError(f"{binary}: no built astrojax to generate the reference pages from; "
                          "build it first (./setup.sh build), or name one with ASTROJAX=PATH")
    run = subprocess.run([str(root / "tests" / "docs" / "generate_pages.sh"), str(binary)],
                         capture_output=True, text=True)
    if run.returncode != 0:
        raise PluginError(f"tests/docs/generate_pages.sh {binary} failed:\n{run.stderr.strip()}")


def on_post_build(config, **kwargs):
    link = pathlib.Path(config.site_dir) / "mathjax"
    if MATHJAX.is_dir() and not link.exists():
        link.unlink(missing_ok=True)  # a dangling link left by an earlier build
        link.symlink_to(MATHJAX, target_is_directory=True)
