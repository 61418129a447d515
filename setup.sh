#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: installs what is missing (apt, idempotent),
# builds in Release, and runs the demo or the tests.
#   ./setup.sh demo        install, build the program, run the main job: sweeps/paper.toml under mpirun,
#                          its thresholds and its figures (out/paper*)
#   ./setup.sh test        install, build, run the default test suite (ctest -L unit)
#   ./setup.sh docs        install, build the program and the live page, build the documentation site offline
#                          (build/site, the live page in build/site/live/)
#   ./setup.sh web         install emscripten, build the live page: the engine in WebAssembly (build/web/index.html)
#   ./setup.sh test-browser  the browser and video tests (ctest -L browser): the live page against the native engine,
#                          the sweep report in headless Chromium, the animations' frames with ffprobe
#   ./setup.sh test-long   install, build, run the long physics validations (ctest -L long)
#   ./setup.sh install | build
#   ./setup.sh peers       also install Boost and SUNDIALS, build astrojax_peers and astrojax_matched (benchmarks only)
#   ./setup.sh test-cluster  also installs slurm-wlm and munge: the cluster scripts on a Slurm started here (ctest -L cluster)
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(build-essential cmake pkg-config libeigen3-dev libopenmpi-dev openmpi-bin
          libhdf5-dev hdf5-tools libcli11-dev libtomlplusplus-dev libfmt-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          python3-numpy python3-h5py python3-matplotlib python3-scipy
          python3-venv python3-setuptools python3-wheel  # pip install -e analysis (docs/guide/analysis)
          zlib1g-dev libdeflate-dev clang libclang-rt-14-dev
          procps   # pgrep, for the fault tests
          git      # the commit --version and every file's provenance name (src/results/source_commit.cmake)
          ffmpeg python3-plotly)  # analysis/animate.py encodes with ffmpeg; analysis/report.py inlines plotly.js
# Only for the work-precision comparison with peer solvers (./setup.sh peers); the product
# never needs them.
PEER_PACKAGES=(libboost-dev libsundials-dev)
# The documentation site (./setup.sh docs) and its tests in the default suite (./setup.sh test):
# MkDocs, its Material theme, the Markdown extensions and MathJax for the equations, all offline.
DOCS_PACKAGES=(mkdocs mkdocs-material python3-pymdownx libjs-mathjax)
# The live page (./setup.sh web, docs, test-browser): Debian's emscripten (it brings Debian's
# nodejs, which its optimiser and the comparison test run under, and node-acorn), and for the
# browser tests headless Chromium, its WebDriver and Selenium.
WEB_PACKAGES=(emscripten nodejs node-acorn chromium chromium-driver python3-selenium)
# Only for ./setup.sh test-cluster: a Slurm and its authentication, started by the test itself.
CLUSTER_PACKAGES=(slurm-wlm munge)
BUILD_DIR=${BUILD_DIR:-build}
# Debian's interpreter: it has python3-numpy/h5py/matplotlib, whatever python3 is first on PATH.
PYTHON=/usr/bin/python3

install() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build() {
  # The product build; ./setup.sh peers turns the peer solvers on for itself only. With a
  # target (build astrojax), only that target and what it needs.
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DASTROJAX_PEERS=OFF >/dev/null
  cmake --build "$BUILD_DIR" -j"$(nproc)" ${1:+--target "$1"}
}

web() {
  # The engine's layers compiled to WebAssembly (web/CMakeLists.txt) and the page beside it.
  # Emscripten's optimiser finds Debian's acorn only on NODE_PATH when node is not Debian's own.
  export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
  emcmake cmake -S web -B "$BUILD_DIR/web" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BUILD_DIR/web" -j"$(nproc)"
  echo "live page: $BUILD_DIR/web/index.html"
}

demo() {
  # The main job: sweeps/paper.toml on the MPI farm (one master, the other ranks workers), the
  # four thresholds of both model variants with their verdicts, the hysteresis diagram and the
  # orbit pictures. Open MPI's mpirun refuses to run as root; there the same sweep runs as one
  # process (the master computes every task: the same file).
  mkdir -p out
  local ranks; ranks=$(( $(nproc) < 2 ? 2 : $(nproc) ))
  local start=$SECONDS
  # An earlier demo that was interrupted left its finished tasks: continue it. One that
  # finished is made again (--force replaces its file).
  local resume=()
  if [ -e out/paper.h5.part ] || [ -e out/paper.h5.journal ]; then
    echo "note: continuing the interrupted main job (out/paper.h5.part)"
    resume=(--resume)
  elif [ -e out/paper.h5 ]; then
    echo "note: out/paper.h5 exists from an earlier demo; making it again"
    resume=(--force)
  fi
  if [ "$(id -u)" -eq 0 ]; then
    echo "note: running as root, where mpirun refuses; running the sweep as one process instead"
    echo "      (as a normal user this is: mpirun -n $ranks $BUILD_DIR/astrojax sweep sweeps/paper.toml)"
    "$BUILD_DIR"/astrojax sweep sweeps/paper.toml -o out/paper.h5 "${resume[@]}"
  else
    mpirun -n "$ranks" "$BUILD_DIR"/astrojax sweep sweeps/paper.toml -o out/paper.h5 "${resume[@]}"
  fi
  "$BUILD_DIR"/astrojax thresholds out/paper.h5 --markdown out/paper_thresholds.md --csv out/paper_thresholds.csv
  "$PYTHON" analysis/plot_hysteresis.py out/paper.h5 --thresholds out/paper_thresholds.csv -o out/paper_hysteresis.png
  "$PYTHON" analysis/plot_orbits.py out/paper.h5 --group up --variant clutch --direction up \
    --classes locked-circular,lagging-circular,flower --top -o out/paper_orbits.png
  "$PYTHON" analysis/report.py out/paper.h5 --thresholds out/paper_thresholds.csv --astrojax "$BUILD_DIR"/astrojax \
    --force -o out/paper.html
  echo
  echo "the main job took $(( SECONDS - start )) s after the build; it wrote:"
  echo "  out/paper.h5                the sweep: every window's class, ω_ball and samples (HDF5)"
  echo "  out/paper_thresholds.md     ω_rise, ω_fall, ω1, ω2 per model variant, brackets and verdicts"
  echo "  out/paper_hysteresis.png    ω_ball against ω_m, one panel per model variant"
  echo "  out/paper_orbits.png        a locked, a lagging and a flower orbit from the top"
  echo "  out/paper.html              the interactive report: hover a point for its class and reason, click it"
  echo "                              for its orbit; opens offline: file://$PWD/out/paper.html"
}

case "${1:-}" in
  install) install ;;
  build) install; build ;;
  demo) install; build astrojax; demo ;;
  docs) PACKAGES+=("${DOCS_PACKAGES[@]}" "${WEB_PACKAGES[@]}"); install; build astrojax; web
        tests/docs/build_docs.sh "$BUILD_DIR"/astrojax "$BUILD_DIR"/site "$BUILD_DIR"/web ;;
  web) PACKAGES+=("${WEB_PACKAGES[@]}"); install; web ;;
  test-browser) PACKAGES+=("${DOCS_PACKAGES[@]}" "${WEB_PACKAGES[@]}"); install; build; web
                tests/docs/build_docs.sh "$BUILD_DIR"/astrojax "$BUILD_DIR"/site "$BUILD_DIR"/web
                (cd "$BUILD_DIR" && ctest -L browser --output-on-failure) ;;
  test) PACKAGES+=("${DOCS_PACKAGES[@]}"); install; build; (cd "$BUILD_DIR" && ctest -L unit -j"$(nproc)" --output-on-failure) ;;
  peers) PACKAGES+=("${PEER_PACKAGES[@]}"); install
         cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DASTROJAX_PEERS=ON >/dev/null
         cmake --build "$BUILD_DIR" -j"$(nproc)" --target astrojax astrojax_peers astrojax_matched ;;
  test-long) install; build; (cd "$BUILD_DIR" && ctest -L long --output-on-failure) ;;
  test-cluster) PACKAGES+=("${CLUSTER_PACKAGES[@]}"); install; build; (cd "$BUILD_DIR" && ctest -L cluster --output-on-failure) ;;
  *) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
