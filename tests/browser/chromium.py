"""Debian's headless Chromium under its chromedriver, driven by python3-selenium, as every test
of the label `browser` starts it (the live page's tests/web/browser_test.py and the report's
tests/browser/report_browser_test.py): one place for the binary's paths and the flags.
"""
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

CHROMIUM = "/usr/bin/chromium"          # Debian's chromium
CHROMEDRIVER = "/usr/bin/chromedriver"  # Debian's chromium-driver


def start(user_dir, size=(1500, 1250), offline=False):
    """A headless Chromium with its own profile in `user_dir`, a window of `size` pixels and the
    console logged (driver.get_log('browser')). `offline`: every request but the file system's
    goes to a dead proxy, so a page that would fetch anything from a network fails to."""
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    flags = ["--headless=new", "--no-sandbox", f"--user-data-dir={user_dir}", f"--window-size={size[0]},{size[1]}",
             "--disable-gpu", "--disable-dev-shm-usage"]
    if offline:
        flags += ["--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>"]
    for flag in flags:
        opts.add_argument(flag)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
