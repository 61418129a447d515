#!/usr/bin/python3
"""An interactive report of a sweep file: one self-contained HTML page that opens offline from
the file system (plotly.js from Debian's python3-plotly is inlined; nothing is fetched).

Per model variant (or grid point), the hysteresis diagram: each classified window a point at
its mean ω_m and its ω_ball, coloured by orbit class as in plot_hysteresis.py, one marker
shape per chain group, each chain's path in protocol order. Windows whose ω_ball is undefined
(the balls too near the axis for an azimuth) sit in a strip of their own below the axis.
Hovering a point shows its chain, group, variant, window, ω_m, ω_ball, class and the
classifier's reason; clicking it draws that window's orbit beside the diagram from the stored
samples (top view x–y and front view x–z, the last --orbit-seconds of the window). Below: the
threshold table of `astrojax thresholds` (brackets, the paper's values and, where it held the
brackets, the verdicts) and the provenance (commit, command line, the sweep file with its
overrides).

The classifier's reasons come from `astrojax windows` (each window classified again from its
stored samples, which gives the stored class back); the thresholds from --thresholds CSV, or
from `astrojax thresholds --no-hold` on the file.

usage: /usr/bin/python3 analysis/report.py out/paper.h5 --thresholds out/paper_thresholds.csv -o out/paper.html
       /usr/bin/python3 analysis/report.py out/quick.h5 -o out/quick.html
"""
import base64
import datetime
import html
import json
import os
import tempfile

import numpy as np

import astrojax_analysis as ajx

PI = ajx.PI
UNDEFINED_STRIP = -0.8   # where windows without an ω_ball sit [π rad/s], below the axis
ARROWS = {1: "▲", -1: "▼", 0: "●"}


def reasons_for(args, path):
    """{(chain, window): reason} from `astrojax windows`, or from --windows CSV."""
    if args.windows:
        rows = ajx.read_astrojax_csv(args.windows, {"chain", "window", "reason"}, "astrojax windows")
    else:
        exe = ajx.require_astrojax(args.astrojax)
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "windows.csv")
            ajx.run_checked([exe, "windows", path, "-o", out])
            rows = ajx.read_astrojax_csv(out, {"chain", "window", "reason"}, "astrojax windows")
    return {(int(r["chain"]), int(r["window"])): r["reason"] for r in rows}


def packed(values):
    """Positions [m] as base64 of little-endian int16 in units of 0.1 mm (±3.2 m)."""
    q = np.clip(np.round(np.nan_to_num(values) * 1e4), -32767, 32767).astype("<i2")
    return base64.b64encode(q.tobytes()).decode("ascii")


def orbit_data(sweep, samples, c, k, seconds):
    """The last `seconds` of window k of chain c: packed r1 and r2 (n × 3), and n."""
    s = samples[(c, k)]
    keep = s["t"] >= s["t"][-1] - seconds
    return {"n": int(keep.sum()), "r1": packed(s["r1"][keep]), "r2": packed(s["r2"][keep])}


def panel_data(sweep, label, chains, reasons, samples, seconds):
    """One diagram's points (one entry per window) and paths (one per chain)."""
    points, paths = [], []
    for c in chains:
        ks = sweep.windows(c)
        xs, ys = [], []
        for k in ks:
            wb = float(sweep.stats["omega_ball"][c, k])
            x = float(sweep.omega_mean[c, k]) / PI
            y = wb / PI if np.isfinite(wb) else None
            xs.append(x)
            ys.append(y)
            points.append({
                "chain": c, "window": k, "x": x, "y": y, "cls": sweep.class_name(c, k),
                "group": sweep.group_name(c), "variant": sweep.variant_name(c),
                "group_index": int(sweep.group[c]) if sweep.is_grouped else 0,
                "dir": ARROWS.get(int(sweep.direction[c, k]), ""),
                "omega_begin": float(sweep.omega_begin[c, k]) / PI, "omega_end": float(sweep.omega_end[c, k]) / PI,
                "reason": reasons.get((c, k), "(no reason: the window has no stored samples)"),
                "orbit": orbit_data(sweep, samples, c, k, seconds) if (c, k) in samples else None,
                "R": sweep.parameter(c, "drive_radius"),
            })
        paths.append({"chain": c, "x": xs, "y": ys, "dir": [int(sweep.direction[c, k]) for k in ks]})
    # The model in every title; the label was made for matplotlib (labels.for_figure), whose
    # escaped '$' reads as '\$' in a page.
    title = label.replace(r"\$", "$") + f" — {sweep.parameter_title(chains[0])}"
    return {"title": title, "points": points, "paths": paths}


def threshold_rows(sweep, rows):
    """The threshold table: one row per chain and threshold, as the CSV has it."""
    out = []
    for r in rows:
        c = int(r["chain"])
        before, after = ajx.number(r["before_rad_s"]) / PI, ajx.number(r["after_rad_s"]) / PI
        paper = ajx.number(r["paper_rad_s"]) / PI
        rel = ajx.number(r["relative_difference"])
        out.append({
            "threshold": ajx.THRESHOLD_SYMBOLS.get(r["threshold"], r["threshold"]),
            "chain": f"{c} ({sweep.group_name(c)}, {sweep.variant_name(c)})" if sweep.is_grouped else str(c),
            "bracket": f"{before:.2f} → {after:.2f}" if np.isfinite(before) else "nothing reached",
            "paper": f"{paper:.2f}" if np.isfinite(paper) else "",
            "difference": f"{100 * rel:+.1f} %" if np.isfinite(rel) else "",
            "verdict": r.get("verdict", "") or "",
            "reason": r.get("verdict_reason", "") or "",
        })
    return out


def page(sweep, panels, table, args):
    """The whole page as one string."""
    import plotly.offline
    text, source, overrides = sweep.config, sweep.config_source, sweep.overrides
    prov = sweep.provenance
    data = {"panels": panels, "colours": sweep.class_colours, "strip": UNDEFINED_STRIP, "orbit_seconds": args.orbit_seconds,
            "groups": sweep.group_names if sweep.is_grouped else []}
    table_html = "".join(
        "<tr>" + "".join(f"<td>{html.escape(str(row[k]))}</td>" for k in
                         ("threshold", "chain", "bracket", "paper", "difference", "verdict")) +
        f"<td class='reason'>{html.escape(row['reason'])}</td></tr>" for row in table)
    verdicts = any(row["verdict"] for row in table)
    prov_items = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>"
                         for k, v in sorted(prov.items()))
    name = os.path.basename(sweep.path)
    panels_html = "".join(
        f"""<section class="variant"><h2>{html.escape(p['title'])}</h2>
<div class="row"><div class="hyst" id="hyst-{i}"></div>
<div class="orbit" id="orbit-{i}"><p class="caption" id="caption-{i}">Click a point of the diagram to see that
window's orbit from the stored samples.</p><div class="view" id="top-{i}"></div><div class="view" id="front-{i}"></div>
</div></div></section>""" for i, p in enumerate(panels))
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")  # no "</script>" inside
    hold_words = "; the verdict comes from holding both sides" if verdicts else " (brackets only: no holds were run)"
    made = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<title>Sweep report: {html.escape(name)}</title>
<style>{CSS}</style>
<script>/* plotly.js, inlined from Debian's python3-plotly (MIT licence) */
{plotly.offline.get_plotlyjs()}</script>
</head><body>
<header><h1>Sweep report: {html.escape(name)}</h1>
<p>The motor-driven Astrojax: two balls on a string whose top a motor carries round a circle of radius R at
ω<sub>m</sub>; the bead slides on the string, the bottom ball is tied to its end. Each point is one measured window of
a chain of runs: the balls' mean angular velocity ω<sub>ball</sub> about the motor axis against the motor's mean
ω<sub>m</sub>, both in π rad/s, coloured by the orbit class the classifier gave it. Hover a point for the
classifier's reason; click it to see that window's orbit. Windows where ω<sub>ball</sub> is undefined (the balls
too near the axis for an azimuth) sit in the strip below the axis. The dotted diagonal is a locked orbit,
ω<sub>ball</sub> = ω<sub>m</sub>.</p></header>
{panels_html}
<section><h2>Thresholds</h2>
<p>From <code>astrojax thresholds</code>: each bracket is the mean ω<sub>m</sub> [π rad/s] of the last window before
the class changed and of the first after{hold_words}.</p>
<table class="thresholds"><thead><tr><th>threshold</th><th>chain</th><th>bracket [π rad/s]</th><th>paper [π]</th>
<th>bracket vs paper</th><th>verdict</th><th>why</th></tr></thead><tbody>{table_html}</tbody></table></section>
<section><h2>Provenance</h2>
<table class="prov">{prov_items}<tr><th>sweep file</th><td>{html.escape(source)}</td></tr>
<tr><th>overrides</th><td>{html.escape(", ".join(overrides) or "none")}</td></tr>
<tr><th>report</th><td>analysis/report.py on {html.escape(name)}, {made}</td></tr></table>
<details><summary>the sweep file as stored in {html.escape(name)} (/config)</summary><pre>{html.escape(text)}</pre></details>
</section>
<script id="data" type="application/json">{payload}</script>
<script>{JS}</script>
</body></html>
"""


CSS = """
body { font-family: "DejaVu Sans", sans-serif; margin: 1em 2em; color: #222; max-width: 1500px; }
h1 { font-size: 1.4em; } h2 { font-size: 1.1em; margin-top: 1.5em; }
.row { display: flex; gap: 1em; align-items: flex-start; }
.hyst { flex: 3; height: 560px; min-width: 500px; }
.orbit { flex: 2; min-width: 360px; }
.view { height: 270px; }
.caption { font-size: 0.9em; min-height: 3em; }
table { border-collapse: collapse; font-size: 0.85em; }
td, th { border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: left; vertical-align: top; }
td.reason { max-width: 40em; }
pre { font-size: 0.8em; background: #f6f6f6; padding: 0.5em; overflow-x: auto; }
"""

# The page's behaviour: the diagrams, the hover text, and the orbit drawn on click.
JS = r"""
const DATA = JSON.parse(document.getElementById('data').textContent);
const SYMBOLS = ['circle', 'square', 'diamond', 'cross', 'x', 'star'];
const PI_TXT = 'π';
// The balls' colours, apart from every orbit class's colour (as plot_orbits.py draws them).
const BEAD = '#882255', BALL = '#332288';
function unpack(b64, n) {
  const bin = atob(b64), bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  const v = new Int16Array(bytes.buffer), out = [[], [], []];
  for (let i = 0; i < n; i++) for (let j = 0; j < 3; j++) out[j].push(v[3 * i + j] * 0.01);  // 0.1 mm -> cm
  return out;
}
function fmt(x) { return x === null ? 'undefined' : x.toFixed(3) + PI_TXT; }
// Text from the file (group and variant names, reasons) shown as text, never read as markup.
function esc(t) { return String(t).replace(/[&<>"']/g, c => ({'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;'})[c]); }
function hover(p) {
  return `chain ${p.chain}${p.group ? ' (' + esc(p.group) + ', ' + esc(p.variant) + ')' : ''}, window ${p.window}<br>` +
         `ω<sub>m</sub> ${p.omega_begin.toFixed(3)} → ${p.omega_end.toFixed(3)}${PI_TXT} rad/s ${p.dir}<br>` +
         `ω<sub>ball</sub> ${fmt(p.y)} rad/s<br>class <b>${esc(p.cls)}</b><br>` +
         `<i>${esc(p.reason).replace(/(.{1,70})(\s|$)/g, '$1<br>')}</i>`;
}
function drawOrbit(i, p) {
  const cap = document.getElementById('caption-' + i);
  cap.innerHTML = `chain ${p.chain}${p.group ? ' (' + esc(p.group) + ', ' + esc(p.variant) + ')' : ''}, window ${p.window}: ` +
    `ω<sub>m</sub> ${p.x.toFixed(2)}π rad/s ${p.dir}, ${esc(p.cls)}, ω<sub>ball</sub> ${fmt(p.y)} rad/s`;
  cap.dataset.chain = p.chain; cap.dataset.window = p.window;
  if (!p.orbit) { cap.textContent += ' (no stored samples)'; return; }
  const r1 = unpack(p.orbit.r1, p.orbit.n), r2 = unpack(p.orbit.r2, p.orbit.n);
  const R = p.R * 100, a = [...Array(101).keys()].map(k => 2 * Math.PI * k / 100);
  const lines = (x, y, name, colour) => ({x, y, name, mode: 'lines', line: {color: colour, width: 1}});
  const last = (x, y, colour) => ({x: [x[x.length - 1]], y: [y[y.length - 1]], mode: 'markers', showlegend: false,
                                    marker: {color: colour, size: 7}, hoverinfo: 'skip'});
  const top = [lines(r1[0], r1[1], 'bead', BEAD), lines(r2[0], r2[1], 'bottom ball', BALL),
               last(r1[0], r1[1], BEAD), last(r2[0], r2[1], BALL),
               {x: a.map(t => R * Math.cos(t)), y: a.map(t => R * Math.sin(t)), mode: 'lines', name: 'drive circle',
                line: {color: 'black', dash: 'dash', width: 0.8}}];
  const front = [lines(r1[0], r1[2], 'bead', BEAD), lines(r2[0], r2[2], 'bottom ball', BALL),
                 last(r1[0], r1[2], BEAD), last(r2[0], r2[2], BALL)];
  const lay = (title, ylab) => ({title: {text: title, font: {size: 12}}, margin: {l: 50, r: 10, t: 30, b: 40},
    xaxis: {title: 'x [cm]'}, yaxis: {title: ylab, scaleanchor: 'x'}, showlegend: title.startsWith('top'),
    legend: {font: {size: 10}}});
  const secs = DATA.orbit_seconds;
  Plotly.react('top-' + i, top, lay(`top view (x–y), the window's last ${secs} s`, 'y [cm]'), {displayModeBar: false});
  Plotly.react('front-' + i, front, lay('front view (x–z)', 'z [cm]'), {displayModeBar: false});
}
DATA.panels.forEach((panel, i) => {
  const traces = [];
  let top = 0;
  panel.points.forEach(p => { top = Math.max(top, p.x, p.y === null ? 0 : p.y); });
  top *= 1.05;
  traces.push({x: [0, top], y: [0, top], mode: 'lines', name: 'ω<sub>ball</sub> = ω<sub>m</sub> (locked)', hoverinfo: 'skip',
               line: {color: 'black', dash: 'dot', width: 1}});
  panel.paths.forEach(path => {
    const x = [], y = [];
    path.x.forEach((xv, j) => { x.push(xv); y.push(path.y[j] === null ? DATA.strip : path.y[j]); });
    traces.push({x, y, mode: 'lines', showlegend: false, hoverinfo: 'skip', line: {color: '#999', width: 0.8}});
  });
  const classes = [...new Set(panel.points.map(p => p.cls))];
  Object.keys(DATA.colours).filter(c => classes.includes(c)).forEach(cls => {
    const pts = panel.points.filter(p => p.cls === cls);
    traces.push({x: pts.map(p => p.x), y: pts.map(p => p.y === null ? DATA.strip : p.y), mode: 'markers', name: cls,
      customdata: pts.map(p => panel.points.indexOf(p)), text: pts.map(hover), hovertemplate: '%{text}<extra></extra>',
      marker: {color: DATA.colours[cls], size: 8, line: {color: 'black', width: 0.5},
               symbol: pts.map(p => (p.y === null ? 'x-thin-open' : SYMBOLS[p.group_index % SYMBOLS.length]))}});
  });
  // The panel's title is the section's heading above it (a plotly title would sit under the mode bar).
  const layout = {hovermode: 'closest', margin: {l: 60, r: 10, t: 40, b: 50},
    xaxis: {title: 'motor ω<sub>m</sub> [π rad/s]', range: [0, top]},
    yaxis: {title: "balls' ω<sub>ball</sub> [π rad/s]", range: [DATA.strip - 0.6, top],
            tickvals: [DATA.strip].concat([...Array(Math.floor(top / 2.5) + 1).keys()].map(k => 2.5 * k)),
            ticktext: ['undefined'].concat([...Array(Math.floor(top / 2.5) + 1).keys()].map(k => String(2.5 * k)))},
    shapes: [{type: 'rect', xref: 'paper', x0: 0, x1: 1, y0: DATA.strip - 0.6, y1: DATA.strip + 0.4,
              fillcolor: '#f0f0f0', line: {width: 0}, layer: 'below'}],
    legend: {orientation: 'h', y: -0.15}};
  if (DATA.groups.length)
    layout.annotations = [{xref: 'paper', yref: 'paper', x: 0, y: 1.0, xanchor: 'left', yanchor: 'bottom',
      showarrow: false, font: {size: 10}, text: 'marker: ' + DATA.groups.map((g, j) => `${esc(g)} ${['●', '■', '◆', '✚', '✖', '★'][j % 6]}`).join(', ') + '; × ω<sub>ball</sub> undefined'}];
  const el = document.getElementById('hyst-' + i);
  Plotly.newPlot(el, traces, layout, {displaylogo: false, responsive: true});
  el.on('plotly_click', ev => {
    const pt = ev.points.find(q => q.customdata !== undefined);
    if (pt) drawOrbit(i, panel.points[pt.customdata]);
  });
});
"""


def main(argv=None):
    ap = ajx.parser(__doc__)
    ap.add_argument("input", help="HDF5 file from `astrojax sweep`")
    ap.add_argument("-o", "--output", required=True, help="HTML page to write")
    ap.add_argument("--windows", metavar="CSV", help="the classifier's reasons from `astrojax windows FILE -o CSV` "
                                                     "(default: run astrojax on the input)")
    ap.add_argument("--orbit-seconds", type=float, default=6.0,
                    help="seconds at the end of each window that its orbit view shows (default 6)")
    ap.add_argument("--force", action="store_true", help="replace an existing output")
    ajx.add_threshold_args(ap)
    args = ap.parse_args(argv)
    if not args.output.lower().endswith(".html"):
        ajx.fail(f"-o {args.output}: the extension must be .html")
    if os.path.exists(args.output) and not args.force:
        ajx.fail(f"-o {args.output}: exists; add --force to replace it")
    if not (np.isfinite(args.orbit_seconds) and args.orbit_seconds > 0):
        ajx.fail(f"--orbit-seconds {args.orbit_seconds}: must be a positive number")
    sweep = ajx.Sweep(args.input)
    chains = [c for c in range(sweep.n_chains) if sweep.valid[c].any()]
    if not chains:
        ajx.fail(f"{args.input}: no classified windows to show")
    rows = ajx.thresholds_for(args, args.input)
    reasons = reasons_for(args, args.input)
    samples = sweep.all_samples()
    panels = [panel_data(sweep, label, cs, reasons, samples, args.orbit_seconds) for label, cs in sweep.groups(chains)]
    text = page(sweep, panels, threshold_rows(sweep, rows), args)
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    tmp = args.output + ".part"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, args.output)
    print(f"wrote {args.output} ({len(text) / 1e6:.1f} MB, {sum(len(p['points']) for p in panels)} windows)")


if __name__ == "__main__":
    ajx.run(main)
