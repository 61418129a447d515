#!/usr/bin/env bash
# Builds the documentation site offline: mkdocs build --strict (a broken link, a missing page or
# any other warning fails), whose hook (tests/docs/mkdocs_hooks.py) first writes the generated
# pages from the given astrojax (tests/docs/generate_pages.sh) and links MathJax into the site;
# then checks every #anchor.
#   tests/docs/build_docs.sh ASTROJAX SITE_DIR
# A plain `mkdocs build` or `mkdocs serve` in the checkout does the same with build/astrojax.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 ASTROJAX SITE_DIR" >&2; exit 2; }
bin=$(realpath "$1")
site=$(realpath -m "$2")
cd "$(dirname "$0")/../.."
[ -x "$bin" ] || { echo "error: $1 is not an executable astrojax" >&2; exit 2; }

ASTROJAX="$bin" mkdocs build --strict --quiet -f mkdocs.yml -d "$site"
# mkdocs checks the pages links point to, not their #anchors: this does.
/usr/bin/python3 tests/docs/check_anchors.py "$site"
echo "site: $site/index.html"
