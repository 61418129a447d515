#!/usr/bin/env bash
# Builds the documentation site offline: mkdocs build --strict (a broken link, a missing page or
# any other warning fails), whose hook (tests/docs/mkdocs_hooks.py) first writes the generated
# pages from the given astrojax (tests/docs/generate_pages.sh) and links MathJax into the site;
# then checks every #anchor.
#   tests/docs/build_docs.sh ASTROJAX SITE_DIR [WEB_DIR]
# WEB_DIR, the WebAssembly build of ./setup.sh web (./setup.sh docs gives it), is copied into
# docs/live/ (git-ignored); without it docs/live/index.html says that this copy of the site was
# built without the live page and how to build it (generate_pages.sh writes that).
# A plain `mkdocs build` or `mkdocs serve` in the checkout does the same with build/astrojax.
set -euo pipefail
[ $# -eq 2 ] || [ $# -eq 3 ] || { echo "usage: $0 ASTROJAX SITE_DIR [WEB_DIR]" >&2; exit 2; }
bin=$(realpath "$1")
site=$(realpath -m "$2")
web=${3:+$(realpath "$3")}
cd "$(dirname "$0")/../.."
[ -x "$bin" ] || { echo "error: $1 is not an executable astrojax" >&2; exit 2; }

if [ -n "$web" ]; then
  rm -rf docs/live
  mkdir -p docs/live
  for f in index.html live.js live.css astrojax.js; do
    [ -f "$web/$f" ] || { echo "error: $web/$f is missing: ./setup.sh web builds it" >&2; exit 1; }
    cp "$web/$f" docs/live/
  done
fi
ASTROJAX="$bin" mkdocs build --strict --quiet -f mkdocs.yml -d "$site"
# mkdocs checks the pages links point to, not their #anchors: this does.
/usr/bin/python3 tests/docs/check_anchors.py "$site"
echo "site: $site/index.html"
