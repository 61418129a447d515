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

Bit for bit if it holds; it does not with Debian's emscripten 3.1.6 (measured: the first
sample of every scene differs in the last bits, 8e-16 m), because both builds evaluate the
same C++ in IEEE-754 double precision (no fused multiply-adds: x86-64 without -march and
wasm32 have none) but with different mathematical libraries (glibc's sin, cos, atan2, exp,
acos against emscripten's musl-derived ones), whose results differ in the last bit.

The tolerance, derived: such a difference (a relative 1e-16 in an evaluation) is far below
what the integrator's error control admits in each step (rtol = 1e-9, atol = 1e-11), so the
WebAssembly result must be as close to the native one as the native one is to the exact
solution. The native result's own error is measured by the same scene at 100 times tighter
tolerances (NAME:tight). The test requires, for each scene:
  * the same number of lines, the same modes on every line, the same event counts and the
    same verdict (the discrete story identical);
  * max |wasm − native| <= max |native − native:tight| over every printed number of the
    scene (positions [m], ω_m [rad/s], the ledger [J]).
It prints the largest differences, and says "bit for bit" if the texts are equal.
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


def numbers(text):
    """Each line's numbers (hex floats), and its words (modes, counts, classes)."""
    nums, words = [], []
    for ln in text.splitlines():
        n, w = [], []
        for tok in ln.split():
            if "0x" in tok or tok.lstrip("-") in ("nan", "inf"):
                n.append(float.fromhex(tok))
            else:
                w.append(tok)
        nums.append(n)
        words.append(w)
    return nums, words


def largest(a, b):
    worst = 0.0
    for x, y in zip(a, b):
        for u, v in zip(x, y):
            if u == u and v == v:  # NaN on both sides (an unreliable ω_ball) compares equal
                worst = max(worst, abs(u - v))
    return worst


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    native, node, module = sys.argv[1:]
    cjs = __file__.replace("compare_native_wasm.py", "web_scenes.cjs")
    ok = True
    for scene, needed in SCENES.items():
        a = report([native, scene])
        t = report([native, scene + ":tight"])
        b = report([node, cjs, module, scene])
        ev = events(a)
        missing = [e for e in needed if int(ev[e]) == 0]
        verdict = next(ln for ln in a.splitlines() if ln.startswith("verdict"))
        print(f"{scene}: {len(a.splitlines())} lines; events {ev}; {verdict.split()[1]}")
        if missing:
            print(f"FAIL: scene {scene} has no {', '.join(missing)}: it does not test what it should")
            ok = False
        if a == b:
            print(f"{scene}: native and WebAssembly identical, bit for bit")
            continue
        na, wa = numbers(a)
        nb, wb = numbers(b)
        nt, _ = numbers(t)
        if len(na) != len(nb) or wa != wb:
            d = first_difference(a, b)
            print(f"FAIL: {scene}: the discrete story differs (lines, modes, events or verdict); first different line "
                  f"{d[0] if d else '-'}:\n  native {d[1] if d else ''}\n  wasm   {d[2] if d else ''}")
            ok = False
            continue
        diff, own = largest(na, nb), largest(na, nt)
        print(f"{scene}: not bit for bit; largest |wasm - native| {diff:.3g}, the native result's own error "
              f"(against rtol/100) {own:.3g}: {'within' if diff <= own else 'BEYOND'}")
        if not diff <= own:
            ok = False
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
