"""Opens HTML reports in headless Chromium and checks that they work (tests/apps/report_browser_test).

    python3 tests/apps/report_browser_check.py [--screenshots DIR] REPORT.html ...

For each page: waits until the page's script says every figure is drawn
(document.body.dataset.plotsRendered, statebench_reports/page.py), then checks
  - no JavaScript console message of level SEVERE (errors, failed resource loads);
  - no failed network request (DevTools' Network.loadingFailed) and no request for anything
    but the file itself or data: / blob: URLs (the page must need nothing else);
  - every plot element drew: Plotly's data has traces, and every trace that has data has a
    drawn SVG path (line, fill, marker or bar) with a non-empty outline.
Prints one JSON object per page (time to render, plots, problems) and exits 1 when any page has
a problem. With --screenshots, saves each page's first screen and each plot as PNG files.

Chromium runs with a fresh empty profile and without network services (the machine may have no
network; the page must not need one).
"""

import argparse
import json
import os
import shutil
import sys
import tempfile
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"

PLOTS_JS = """
return Array.from(document.querySelectorAll('.sb-plot')).map(function (gd) {
  var data = gd.data || [];
  var withData = data.filter(function (t) {
    var v = (t.type === 'bar' ? t.y : (t.y || t.x)) || [];
    return Array.prototype.some.call(v, function (x) { return x !== null && x !== undefined; });
  }).length;
  var drawn = 0;
  gd.querySelectorAll('.scatterlayer .trace, .barlayer .trace').forEach(function (tr) {
    var paths = tr.querySelectorAll('path');
    for (var i = 0; i < paths.length; ++i) {
      var d = paths[i].getAttribute('d');
      if (d && d.length > 4 && d !== 'M0,0Z') { drawn++; break; }
    }
  });
  return {id: gd.id, traces: data.length, traces_with_data: withData, traces_drawn: drawn,
          width: gd.clientWidth, height: gd.clientHeight,
          has_layout: !!gd._fullLayout};
});
"""


def start_browser(profile):
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--disable-dev-shm-usage",
                 "--window-size=1400,1800", f"--user-data-dir={profile}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def network_problems(driver, page_url):
    """Failed loads and requests for anything but the page itself, of the page's own document
    (the browser's start page before it has requests of its own)."""
    failed, foreign = [], []
    ours = {}  # requestId -> url, for the requests the page made
    events = [json.loads(e["message"])["message"] for e in driver.get_log("performance")]
    for message in events:
        params = message.get("params", {})
        if message.get("method") == "Network.requestWillBeSent" and \
                params.get("documentURL") == page_url:
            url = params.get("request", {}).get("url", "")
            ours[params.get("requestId")] = url
            if url != page_url and not url.startswith(("data:", "blob:")):
                foreign.append(url)
    for message in events:
        params = message.get("params", {})
        if message.get("method") == "Network.loadingFailed" and params.get("requestId") in ours:
            failed.append(f"{ours[params['requestId']]}: {params.get('errorText', '?')}")
    if page_url not in ours.values():
        failed.append(f"{page_url}: no request for the page seen")
    return failed, foreign


def check(driver, path, screenshots, timeout_s):
    url = "file://" + os.path.abspath(path)
    driver.get_log("browser")  # empty the logs of the page before
    driver.get_log("performance")
    start = time.monotonic()
    driver.get(url)
    WebDriverWait(driver, timeout_s, poll_frequency=0.05).until(
        lambda d: d.execute_script("return document.body && (document.body.dataset.plotsRendered"
                                   " || document.body.dataset.plotsFailed)"))
    render_s = time.monotonic() - start
    result = {"file": path, "bytes": os.path.getsize(path), "render_s": round(render_s, 3)}
    problems = []
    failed_plot = driver.execute_script("return document.body.dataset.plotsFailed || ''")
    if failed_plot:
        problems.append("a plot failed: " + failed_plot)
    console = [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]
    problems += ["console: " + e.get("message", "") for e in console]
    failed, foreign = network_problems(driver, url)
    problems += ["failed load: " + f for f in failed]
    problems += ["request for something else than the page: " + f for f in foreign]
    plots = driver.execute_script(PLOTS_JS)
    rendered = int(driver.execute_script("return document.body.dataset.plotsRendered || '0'"))
    if rendered != len(plots):
        problems.append(f"{rendered} figures drawn of {len(plots)} plot elements")
    if not plots:
        problems.append("no plot on the page")
    for p in plots:
        if not p["has_layout"] or p["traces"] == 0:
            problems.append(f"plot {p['id']}: not drawn (no traces)")
        elif p["traces_drawn"] < p["traces_with_data"] or p["traces_drawn"] == 0:
            problems.append(f"plot {p['id']}: {p['traces_drawn']} traces drawn of "
                            f"{p['traces_with_data']} with data")
        if p["width"] < 100 or p["height"] < 100:
            problems.append(f"plot {p['id']}: {p['width']}x{p['height']} px")
    result["plots"] = len(plots)
    result["traces_drawn"] = sum(p["traces_drawn"] for p in plots)
    result["problems"] = problems
    if screenshots:
        os.makedirs(screenshots, exist_ok=True)
        stem = os.path.splitext(os.path.basename(path))[0]
        driver.save_screenshot(os.path.join(screenshots, f"{stem}_top.png"))
        # The page's sticky menu would cover the top of each plot's screenshot.
        driver.execute_script("var n = document.querySelector('nav'); if (n) n.style.position = 'static';")
        for p in plots:
            element = driver.find_element(By.ID, p["id"])
            driver.execute_script("arguments[0].scrollIntoView()", element)
            element.screenshot(os.path.join(screenshots, f"{stem}_{p['id']}.png"))
    return result


def main(argv):
    parser = argparse.ArgumentParser()
    parser.add_argument("--screenshots", help="folder for PNG screenshots")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds to wait per page")
    parser.add_argument("pages", nargs="+")
    args = parser.parse_args(argv)
    profile = tempfile.mkdtemp(prefix=f"report_browser_check_{os.getpid()}_")
    driver = None
    ok = True
    try:
        driver = start_browser(profile)
        for path in args.pages:
            if not os.path.isfile(path):
                print(json.dumps({"file": path, "problems": ["no such file"]}))
                ok = False
                continue
            try:
                result = check(driver, path, args.screenshots, args.timeout)
            except Exception as e:  # noqa: BLE001 - a timeout or a browser failure is a problem
                result = {"file": path, "problems": [f"{type(e).__name__}: {e}"]}
            ok = ok and not result["problems"]
            print(json.dumps(result), flush=True)
    finally:
        if driver is not None:
            driver.quit()
        shutil.rmtree(profile, ignore_errors=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
