"""astrojax_analysis: the package behind the analysis scripts (analysis/*.py).

Reading files: `Sweep(path)` (a sweep file, validated on open), `read_run(path)` (a run
file's trajectory), `read_motion(path)` (a run or replay file as an animation reads it); all
raise `SweepFileError` (path, dataset, message) for a file that is missing, damaged, of a
newer format or not what the layout says. Orbit classes come from the
file's /classes (format 3) or the one fallback table (classes.FALLBACK). Thresholds come from
`astrojax thresholds` (thresholds.py), figures from plotting.py; run_ledger, tie scans, the
threshold fit and work-precision tables live in ledger.py, tie.py, fit.py and
workprecision.py. Scripts are thin wrappers: `cli.run(main)` turns every refusal into one
line `error: ...` and exit 2.

Install: `python3 -m venv --system-site-packages VENV && VENV/bin/pip install -e analysis`
(docs/guide/analysis/), or run the scripts in place: they sit next to this package.
"""
from . import basins
from .classes import CLASS_COLOURS, FALLBACK as FALLBACK_CLASSES, STEADY_CLASSES, OrbitClass
from .cli import float_list, parser, run
from .errors import SweepFileError, fail
from .labels import ellipsize, for_figure, printable
from .motion import corotating, run_parameter, window_phase
from .orbits import Curves
from .optimize import nelder_mead, scan_and_refine
from .plotting import (BRACKET_SHADE, MODE_COLOURS, MODE_NAMES, PAPER_LINE, PI, THRESHOLD_SYMBOLS, add_figure_args,
                       check_output, draw_thresholds, figure_size, legend, legend_columns, legend_height, new_figure,
                       panel_grid, panels, paper_values, place_upright_labels, pyplot, runs, save, sweep_for_plot,
                       threshold_legend_handles)
from .reader import (FORMAT_VERSION, SweepFile, as_text, file_kind, format_version, open_h5, read_motion, read_run,
                     resolved)
from .sweep import DIRECTION_MARKERS, DIRECTION_WORDS, GROUP_MARKERS, SEED_MARKERS, Sweep, require_phase, select_chains
from .thresholds import (add_threshold_args, find_astrojax, number, read_astrojax_csv, read_sequence_csv,
                         read_thresholds_csv, require_astrojax, run_checked, run_sequence, run_thresholds,
                         thresholds_for, write_report)

__version__ = "0.1.0"
