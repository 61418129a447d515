#!/usr/bin/python3
"""The interactive report in a real browser: headless Chromium (Debian's chromium and
chromium-driver, driven by python3-selenium) opens the page from the file system with the
network switched off, and
- finds no console errors (severity SEVERE) and a diagram per variant drawn by plotly.js;
- hovers one point of each orbit class and reads its hover text: chain, window, class and the
  classifier's reason, as `astrojax windows` gives them;
- clicks it and finds the orbit panel naming that chain and window, its top and front views
  drawn with as many points as the report stores for that window.
A screenshot of the page after the last click goes to WORK_DIR/report.png.
Before the browser, bad input: a file without samples, a missing file and an existing output
without --force each exit 2 with one line naming the file and the problem, and write nothing.

usage: report_browser_test.py ASTROJAX SOURCE_DIR WORK_DIR
"""
import csv
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

failures = []


def check(what, ok):
    print(f"{'ok  ' if ok else 'FAIL'} {what}")
    if not ok:
        failures.append(what)


def run(*cmd):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True)
    if p.returncode != 0:
        print(p.stdout, p.stderr)
    return p


def browser(user_dir):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import chromium
    return chromium.start(user_dir, size=(1500, 1300), offline=True)


POINT_JS = """
const [panel, chain, window] = arguments;
const gd = document.getElementById('hyst-' + panel), fl = gd._fullLayout;
gd.scrollIntoView({block: 'center'});  // offsets are from the centre of the element's visible part
for (const tr of gd.data) {
  if (!tr.customdata) continue;
  for (let j = 0; j < tr.customdata.length; j++) {
    const p = DATA.panels[panel].points[tr.customdata[j]];
    if (p.chain === chain && p.window === window) {
      const r = gd.getBoundingClientRect();
      return [fl.xaxis.l2p(tr.x[j]) + fl.xaxis._offset - r.width / 2, fl.yaxis.l2p(tr.y[j]) + fl.yaxis._offset - r.height / 2,
              p.orbit ? p.orbit.n : 0];
    }
  }
}
return null;
"""


def check_bad_input(src, exe, h5, work):
    import h5py
    report = ["/usr/bin/python3", os.path.join(src, "analysis", "report.py")]
    bare = os.path.join(work, "no_samples.h5")
    shutil.copy(h5, bare)
    with h5py.File(bare, "a") as f:
        del f["samples"]
    exists = os.path.join(work, "exists.html")
    with open(exists, "w") as f:
        f.write("keep me")
    out = os.path.join(work, "bad.html")
    for name, args, needles in (
            ("file without samples", [bare, "-o", out], [bare, "/samples", "no samples"]),
            ("missing file", [os.path.join(work, "nope.h5"), "-o", out], ["nope.h5", "no such file"]),
            ("existing output", [h5, "-o", exists], [exists, "exists", "--force"])):
        p = subprocess.run(report + args + ["--astrojax", exe], capture_output=True, text=True)
        msg = p.stderr.strip()
        check(f"report.py, {name}: exit 2, one line naming it ({msg})",
              p.returncode == 2 and len(msg.splitlines()) == 1 and all(n in msg for n in needles)
              and "Traceback" not in msg)
    check("report.py's bad input wrote nothing", not any(n.startswith("bad.html") for n in os.listdir(work)))
    check("report.py left the existing output as it was", open(exists).read() == "keep me")


def main():
    exe, src, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    h5, page = os.path.join(work, "three_orbits.h5"), os.path.join(work, "report.html")
    run(exe, "sweep", os.path.join(src, "tests", "data", "replay_three_orbits.toml"), "-o", h5, "--force", "-q")
    check_bad_input(src, exe, h5, work)
    wcsv = os.path.join(work, "windows.csv")
    run(exe, "windows", h5, "-o", wcsv, "--force")
    with open(wcsv, newline="") as f:
        rows = list(csv.DictReader(f))
    p = run("/usr/bin/python3", os.path.join(src, "analysis", "report.py"), h5, "-o", page, "--force",
            "--astrojax", exe)
    check(f"report.py exits 0 ({p.stderr.strip()})", p.returncode == 0 and os.path.exists(page))
    text = open(page, encoding="utf-8").read()
    head, rest = text.split("<script>", 1)
    page_own = head + rest.split("</script>", 1)[1]  # the page without the inlined plotly.js
    check("the page fetches nothing: no tag with an http(s) or protocol-relative src or href", not re.search(
        r"<(script|link|img|iframe|video|source)\b[^>]*\b(src|href)\s*=\s*[\"']?(https?:|//)", page_own, re.I))
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    user_dir = tempfile.mkdtemp(prefix="ajx-chromium-")
    driver = browser(user_dir)
    try:
        driver.get("file://" + os.path.abspath(page))
        time.sleep(2)
        check("plotly.js loaded and a diagram drawn", driver.execute_script(
            "return typeof Plotly !== 'undefined' && document.querySelectorAll('.hyst .main-svg').length > 0"))
        for row in rows:
            c, k, cls = int(row["chain"]), int(row["window"]), row["class"]
            found = driver.execute_script(POINT_JS, 0, c, k)
            check(f"window {k} ({cls}) is a point of the diagram", found is not None)
            if not found:
                continue
            dx, dy, n = found
            el = driver.find_element(By.ID, "hyst-0")
            ActionChains(driver).move_to_element_with_offset(el, int(dx), int(dy)).perform()
            time.sleep(0.5)
            hover = " ".join(e.text for e in driver.find_elements(By.CSS_SELECTOR, ".hoverlayer .hovertext"))
            check(f"hover on window {k}: chain, window and class shown ({hover[:80]!r}...)",
                  f"chain {c}" in hover and f"window {k}" in hover and cls in hover)
            first_words = " ".join(row["reason"].split()[:4])
            check(f"hover on window {k}: the classifier's reason shown ({first_words!r})",
                  first_words in " ".join(hover.split()))
            ActionChains(driver).move_to_element_with_offset(el, int(dx), int(dy)).click().perform()
            time.sleep(0.8)
            cap = driver.find_element(By.ID, "caption-0")
            check(f"click on window {k}: the orbit panel names it ({cap.text!r})",
                  cap.get_attribute("data-chain") == str(c) and cap.get_attribute("data-window") == str(k)
                  and f"window {k}" in cap.text and cls in cap.text)
            drawn = driver.execute_script(
                "const t = document.getElementById('top-0'), f = document.getElementById('front-0');"
                "return [t.data ? t.data[0].x.length : 0, f.data ? f.data[0].x.length : 0];")
            check(f"click on window {k}: top and front views drawn with its {n} stored points ({drawn})",
                  n > 10 and drawn == [n, n])
        driver.save_screenshot(os.path.join(work, "report.png"))
        severe = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        check(f"no console errors ({severe})", not severe)
    finally:
        driver.quit()
        shutil.rmtree(user_dir, ignore_errors=True)
    print(f"{len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
