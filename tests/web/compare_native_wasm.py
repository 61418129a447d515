#!/usr/bin/python3
"""The same scenes in the native build and in the WebAssembly module: are the numbers the same?

    compare_native_wasm.py WEB_SCENES NODE ASTROJAX_JS

WEB_SCENES is the native build of src/web/scenes.cpp (tests/web/web_scenes.cpp), ASTROJAX_JS
the module of ./setup.sh web, run under NODE by tests/web/web_scenes.cjs. Both print, for each
scene, one line every 15 frames of 1/60 s: t, ω_m, the mode, a, r1, r2 and the energy ledger,
every double in hexadecimal (exact), then the event counts and the classifier's verdict.

The scenes (src/web/scenes.cpp): "locked", the paper's Table 1 orbit held at 4.5π rad/s;
"climb", from rest with ω_m ramped at 1 rad/s² to 14π, where the bead sticks and slips;
"slack", the Table 1 orbit with the motor braked at 200 rad/s², the string going slack and
jerking taut again. Each scene must show its events (a stick, an impact), or the comparison
would not cover them.

The comparison is bit for bit: the two texts must be identical. Both builds evaluate the same
C++ in IEEE-754 double precision without contraction into fused multiply-adds (x86-64 without
-march has no FMA; wasm32 has none), so they differ only where a library function (exp, sin,
cos, atan2, pow, sqrt is exact) returns a different last bit, and then the first differing
line is printed with the largest difference, and the test fails.
"""
import subprocess
import sys

SCENES = {  # scene -> the events it must contain (a count that must be > 0)
    "locked": [],
    "climb": ["sticks"],
    "slack": ["impacts"],
}


def report(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(f"FAIL: {' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
        sys.exit(1)
    return r.stdout


def events(text):
    line = next(ln for ln in text.splitlines() if ln.startswith("events "))
    w = line.split()[1:]
    return {w[i]: w[i + 1] for i in range(0, len(w), 2)}


def first_difference(a, b):
    for i, (x, y) in enumerate(zip(a.splitlines(), b.splitlines())):
        if x != y:
            worst = 0.0
            for u, v in zip(x.split(), y.split()):
                try:
                    worst = max(worst, abs(float.fromhex(u) - float.fromhex(v)))
                except ValueError:
                    pass
            return i + 1, x, y, worst
    return None


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    native, node, module = sys.argv[1:]
    ok = True
    for scene, needed in SCENES.items():
        a = report([native, scene])
        b = report([node, __file__.replace("compare_native_wasm.py", "web_scenes.cjs"), module, scene])
        lines = len(a.splitlines())
        ev = events(a)
        missing = [e for e in needed if int(ev[e]) == 0]
        verdict = next(ln for ln in a.splitlines() if ln.startswith("verdict"))
        print(f"{scene}: {lines} lines; events {ev}; {verdict.split()[1]}")
        if missing:
            print(f"FAIL: scene {scene} has no {', '.join(missing)}: it does not test what it should")
            ok = False
        if a == b:
            print(f"{scene}: native and WebAssembly identical, bit for bit")
            continue
        ok = False
        d = first_difference(a, b)
        if d is None:
            print(f"FAIL: {scene}: one report is longer ({lines} against {len(b.splitlines())} lines)")
        else:
            n, x, y, worst = d
            print(f"FAIL: {scene}: first difference at line {n} (largest |difference| {worst:.3g}):\n"
                  f"  native {x}\n  wasm   {y}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
