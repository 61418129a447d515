#!/usr/bin/env bash
# analysis/ as an installable package, offline: a venv that sees Debian's numpy, h5py,
# matplotlib and scipy, `pip install -e analysis` with no index at all, then the package
# imported from outside the checkout (its reader and SweepFileError), and the source folder left
# as it was. usage: analysis_package_test.sh SOURCE_DIR PYTHON
set -euo pipefail
src=$(cd "$1" && pwd); python=${2:-/usr/bin/python3}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
before=$(cd "$src/analysis" && find . -path ./astrojax_analysis/__pycache__ -prune -o -print | sort)
"$python" -m venv --system-site-packages "$tmp/venv"
"$tmp/venv/bin/pip" install --no-index --quiet -e "$src/analysis"
cd "$tmp"
"$tmp/venv/bin/python" - "$src" <<'PY'
import os, sys
import astrojax_analysis as ajx
src = sys.argv[1]
assert ajx.__file__ == os.path.join(src, "analysis", "astrojax_analysis", "__init__.py"), ajx.__file__
try:
    ajx.Sweep("no_such_file.h5")
except ajx.SweepFileError as e:
    assert (e.path, e.dataset, e.message) == ("no_such_file.h5", None, "no such file"), e
else:
    raise AssertionError("no SweepFileError")
print("installed:", ajx.__file__)
PY
after=$(cd "$src/analysis" && find . -path ./astrojax_analysis/__pycache__ -prune -o -print | sort)
if [ "$before" != "$after" ]; then
  echo "pip install -e left files in analysis/:"; diff <(echo "$before") <(echo "$after") || true; exit 1
fi
echo ok
