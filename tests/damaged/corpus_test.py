#!/usr/bin/python3
"""The damaged-file corpus against every C++ reader of sweep files.

    corpus_test.py ASTROJAX SOURCE_DIR [WORK_DIR]

Runs the small grouped sweep tests/damaged/tiny_grouped.toml, makes its damaged copies
(make_corpus.py, at least 60), and runs `astrojax thresholds --no-hold --csv --sequence-csv`,
`astrojax classify -o COPY` and `astrojax verify` on the undamaged file and on each copy.
For every copy it asserts:
  - no command crashes: exit 0 or 2 only (no signal, no abort, no uncaught exception), and a
    refusal says `error:` and names the input file;
  - a reader (thresholds, classify) either refuses the copy or gives exactly the undamaged
    file's output (its tables, its CSVs, the reclassified copy's /windows);
  - whenever a reader's output differs from the undamaged file's (a refusal included),
    `astrojax verify` exits 2 and names the damaged dataset (for damage to /samples, the window
    whose samples no longer give its /windows row);
  - classify's refusal leaves nothing behind: no copy, no temporary file;
  - nothing printed holds a control character (labels with escapes are printed escaped).
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_corpus  # noqa: E402

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")


def run(cmd, cwd):
    p = subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, timeout=300)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def windows_dump(path):
    """The reclassified copy's /windows, as bytes per dataset."""
    with h5py.File(path, "r") as f:
        return {k: np.asarray(v[()]).tobytes() for k, v in f["windows"].items()}


def readers(astrojax, path, work):
    """What the C++ readers make of `path`: {reader: (exit code, output)}, and the problems."""
    out, problems = {}, []
    tag = os.path.basename(path)
    csv, seq, copy = (os.path.join(work, f"{tag}.{x}") for x in ("csv", "seq.csv", "copy.h5"))
    for f in (csv, seq, copy):
        if os.path.exists(f):
            os.remove(f)
    rc, so, se = run([astrojax, "thresholds", path, "--no-hold", "--csv", csv, "--sequence-csv", seq], work)
    files = tuple(open(f).read() if os.path.exists(f) else None for f in (csv, seq)) if rc == 0 else ()
    out["thresholds"] = (rc, so.replace(path, "FILE") if rc == 0 else "", files)
    problems += check_exit("thresholds", rc, so, se, path)
    before = set(os.listdir(work))
    rc, so, se = run([astrojax, "classify", path, "-o", copy], work)
    problems += check_exit("classify", rc, so, se, path)
    if rc == 0:
        out["classify"] = (rc, so.replace(copy, "COPY"), windows_dump(copy))
        os.remove(copy)
    else:
        out["classify"] = (rc, "", None)
        left = set(os.listdir(work)) - before
        if left:
            problems.append(f"classify refused but left behind {sorted(left)}")
    return out, problems


def check_exit(what, rc, so, se, path, refuses_on_stderr=True):
    p = []
    if rc not in (0, 2):
        p.append(f"{what}: exit {rc} (a crash?): {se.strip()[-300:]}")
    if rc == 2 and refuses_on_stderr and ("error:" not in se or path not in se):
        p.append(f"{what}: exit 2 without 'error: {path}': {se.strip()[-300:]}")
    if "terminate called" in se or "Traceback" in se:
        p.append(f"{what}: {se.strip()[-300:]}")
    if CONTROL.search(so) or CONTROL.search(se):
        p.append(f"{what}: prints a control character")
    return p


def names_damage(text, dataset):
    """Whether verify's report names the damaged dataset (or, for /samples, the windows whose
    samples no longer match /windows)."""
    if not dataset:
        return True
    if dataset.startswith("samples/") and "/samples" in text:
        return True
    return dataset.lstrip("@") in text


def main():
    astrojax, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    work = sys.argv[3] if len(sys.argv) > 3 else tempfile.mkdtemp(prefix="astrojax-damaged-")
    os.makedirs(work, exist_ok=True)
    for old in ("run", "corpus"):  # a rerun starts afresh
        shutil.rmtree(os.path.join(work, old), ignore_errors=True)
    source = os.path.join(work, "source.h5")
    rc, so, se = run([astrojax, "sweep", os.path.join(src, "tests/damaged/tiny_grouped.toml"), "-o", source, "-q",
                      "--force"], work)
    if rc != 0:
        print(f"FAIL: the source sweep: exit {rc}: {so}{se}")
        return 1
    rc, so, _ = run([astrojax, "verify", source], work)
    if rc != 0:
        print(f"FAIL: verify on the undamaged file: exit {rc}: {so}")
        return 1
    corpus = make_corpus.make(source, os.path.join(work, "corpus"))
    if len(corpus) < 60:
        print(f"FAIL: only {len(corpus)} damaged copies")
        return 1
    os.makedirs(os.path.join(work, "run", "undamaged"))
    base, problems = readers(astrojax, source, os.path.join(work, "run", "undamaged"))
    if problems or any(v[0] != 0 for v in base.values()):
        print(f"FAIL: the undamaged file: {problems} {[(k, v[0]) for k, v in base.items()]}")
        return 1
    def one(case):
        name, path, dataset, what = case
        own = os.path.join(work, "run", name)  # each case's outputs apart: the cases run side by side
        os.makedirs(own)
        got, problems = readers(astrojax, path, own)
        rc, so, se = run([astrojax, "verify", path], own)
        problems += check_exit("verify", rc, so, se, path, refuses_on_stderr=False)
        changed = [k for k in got if got[k] != base[k]]
        if changed:
            if rc == 0:
                problems.append(f"the output of {', '.join(changed)} differs, yet verify says ok")
            elif not names_damage(so, dataset):
                problems.append(f"verify does not name {dataset}: {so.strip()[-300:]}")
        if rc != 0 and "DAMAGED" not in so:
            problems.append(f"verify exit {rc} without DAMAGED: {so.strip()[-200:]}{se.strip()[-200:]}")
        return (bool(changed), any(got[k][0] != 0 for k in got), rc != 0,
                [f"{name} ({what}): {p}" for p in problems])

    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(one, corpus))
    differ = sum(r[0] for r in results)
    refused = sum(r[1] for r in results)
    flagged = sum(r[2] for r in results)
    fails = [f for r in results for f in r[3]]
    # The same file as format 2 wrote it (joined strings, no /classes) reads the same.
    old = make_corpus.as_format_2(source, os.path.join(work, "format2.h5"))
    os.makedirs(os.path.join(work, "run", "format2"))
    got, problems = readers(astrojax, old, os.path.join(work, "run", "format2"))
    rc, so, se = run([astrojax, "verify", old], work)
    fails += [f"format 2: {p}" for p in problems]
    fails += [f"format 2: the output of {k} differs" for k in got if got[k] != base[k]]
    if rc != 0:
        fails.append(f"format 2: verify exit {rc}: {so.strip()[-300:]}")
    print(f"{len(corpus)} damaged copies: {differ} change a reader's output (each caught by verify unless listed "
          f"below), {refused} refused by a reader, {flagged} flagged by verify")
    for f in fails:
        print("FAIL:", f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
