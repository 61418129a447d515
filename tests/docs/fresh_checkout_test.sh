#!/usr/bin/env bash
# The habits of every MkDocs user, in a fresh copy of the checkout (its tracked files, nothing
# generated) whose build/astrojax is the program under test, as after ./setup.sh build:
# `mkdocs build --strict` builds the site (the hook writes the generated pages), and
# `mkdocs serve` serves them, without rebuilding forever on its own writes.
# Usage: fresh_checkout_test.sh ASTROJAX SOURCE_DIR
set -u
bin=$(realpath "$1"); src=$2
source "$(dirname "$0")/../check.sh"
copy=$work/checkout
mkdir -p "$copy/build"
git -C "$src" ls-files -z | tar -C "$src" --null -T - -cf - | tar -x -C "$copy"
ln -s "$bin" "$copy/build/astrojax"
check "the copy has no generated page" "[ ! -e '$copy/docs/reference/cli.md' ] && [ ! -e '$copy/docs/figures' ]"

(cd "$copy" && mkdocs build --strict --quiet) > "$work/build.out" 2>&1
rc=$?
check "mkdocs build --strict in a fresh checkout: exit 0 (exit $rc: $(tail -3 "$work/build.out"))" "[ $rc -eq 0 ]"
check "the generated pages and figures are in the site" \
  "grep -q 'astrojax sweep' '$copy/site/reference/cli.html' && grep -q 'drive_radius' '$copy/site/reference/configuration.html' && ls '$copy'/site/figures/*.png > /dev/null"
check "MathJax linked into the site" "[ -e '$copy/site/mathjax/MathJax.js' ]"

# Without a built program: a clear error naming what to do, no traceback.
mv "$copy/build/astrojax" "$copy/build/astrojax.away"
(cd "$copy" && mkdocs build --strict --quiet) > "$work/nobin.out" 2>&1
rc=$?
check "no built program: mkdocs fails saying to build it (exit $rc: $(grep -m1 -i error "$work/nobin.out"))" \
  "[ $rc -ne 0 ] && grep -q './setup.sh build' '$work/nobin.out' && ! grep -q Traceback '$work/nobin.out'"
mv "$copy/build/astrojax.away" "$copy/build/astrojax"

port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
(cd "$copy" && exec mkdocs serve -a "127.0.0.1:$port") > "$work/serve.out" 2>&1 &
serve=$!
page=""
for _ in $(seq 600); do
  page=$(/usr/bin/python3 -c "import urllib.request as u; print(u.urlopen('http://127.0.0.1:$port/reference/cli.html', timeout=2).read().decode())" 2> /dev/null) && break
  kill -0 $serve 2> /dev/null || break
  sleep 0.1
done
check "mkdocs serve serves the generated reference ($(tail -2 "$work/serve.out"))" "grep -q 'astrojax sweep' <<< \"\$page\""
sleep 3  # a hook that rewrote its pages at every build would be rebuilding by now
check "mkdocs serve does not rebuild on its own writes" "! grep -q 'Detected file changes' '$work/serve.out'"
kill $serve; wait $serve 2> /dev/null
finish "docs_fresh_checkout"
