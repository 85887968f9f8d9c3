#!/usr/bin/env python3
"""Tests a study's report.html (the viewer of src/study/report_viewer.html) in headless Chromium through
Selenium: the page loads from file:// and draws its four panels, the keys select variants and sample counts,
the exposure slider changes the images, wheel zoom and drag pan move all four panels in step, a table header
sorts its rows, and the page makes no network request and logs no error.

Usage:
  test_report_html.py --report REPORT.html [--screenshot OUT.png]
  test_report_html.py --mock TEMPLATE [--screenshot OUT.png]   (fills TEMPLATE with mock_report.py first)
Prints one line per check; exits 0 when all pass, 1 at the first failure (2 on bad arguments).
Needs /usr/bin/chromium, /usr/bin/chromedriver and python3-selenium: `bash scripts/setup.sh` installs them.
"""
import argparse
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
HERE = os.path.dirname(os.path.abspath(__file__))
FLAGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-default-apps", "--window-size=1400,1000"]
PANELS = ["reference", "variant", "error", "flip"]


class CheckFailed(Exception):
    pass


def require(condition, message):
    if not condition:
        raise CheckFailed(message)


def ok(name, detail=""):
    print(f"ok    {name}" + (f": {detail}" if detail else ""), flush=True)


def skip(name, why):
    print(f"skip  {name}: {why}", flush=True)


# A canvas's pixels: an FNV-1a hash of its RGBA bytes, its number of distinct colours, and a hash and count
# of the opaque pixels (the region where the image was drawn; outside it the canvas stays transparent).
PIXELS_JS = """
const c = arguments[0], d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
let h = 2166136261, m = 2166136261, opaque = 0;
const colours = new Set();
for (let i = 0; i < d.length; i += 4) {
  for (let k = 0; k < 4; k++) h = Math.imul(h ^ d[i + k], 16777619) >>> 0;
  colours.add((d[i] << 24 | d[i + 1] << 16 | d[i + 2] << 8 | d[i + 3]) >>> 0);
  const a = d[i + 3] === 255 ? 1 : 0;
  opaque += a;
  m = Math.imul(m ^ a, 16777619) >>> 0;
}
return {hash: h, colours: colours.size, mask: m, opaque: opaque, pixels: d.length / 4};
"""


class Page:
    def __init__(self, driver):
        self.d = driver

    def js(self, script, *args):
        return self.d.execute_script(script, *args)

    def state(self):
        return self.js("return window.symphongViewer ? window.symphongViewer.state() : null;")

    def canvas(self, name):
        from selenium.webdriver.common.by import By
        return self.d.find_element(By.CSS_SELECTOR, f'canvas.panel[data-panel="{name}"]')

    def pixels(self, name):
        return self.js(PIXELS_JS, self.canvas(name))

    def all_pixels(self):
        return {name: self.pixels(name) for name in PANELS}

    def drawn(self):
        return {name: int(self.canvas(name).get_attribute("data-drawn")) for name in PANELS}

    def data(self):
        return self.js("return JSON.parse(document.getElementById('study-data').textContent);")

    def key(self, keys):
        from selenium.webdriver.common.by import By
        from selenium.webdriver.common.action_chains import ActionChains
        try:
            self.d.find_element(By.TAG_NAME, "body").send_keys(keys)
        except Exception:  # a driver that will not type into <body>: type into the focused element
            ActionChains(self.d).send_keys(keys).perform()

    def pixel_at(self, name, x, y):
        return self.js("return window.symphongViewer.imagePixelAt(arguments[0], arguments[1], arguments[2]);",
                       self.canvas(name), x, y)

    def size(self, name):
        return self.js("const r = arguments[0].getBoundingClientRect(); return [r.width, r.height];", self.canvas(name))


def same_view(page, what):
    """All four panels drew the same view: the same image pixel at their centre and corners, the same
    drawn (opaque) region. Returns the image pixel at the centre."""
    w, h = page.size("variant")
    points = [(w / 2, h / 2), (3, 3), (w - 4, h - 4)]
    seen = {name: [page.pixel_at(name, x, y) for x, y in points] for name in PANELS}
    require(all(v == seen["variant"] for v in seen.values()),
            f"{what}: the panels show different views (image pixels at centre and corners: {seen})")
    masks = {name: (p["mask"], p["opaque"]) for name, p in page.all_pixels().items()}
    require(len(set(masks.values())) == 1, f"{what}: the panels' drawn regions differ (opaque pixels: {masks})")
    return seen["variant"][0], masks["variant"][1]


def check_loaded(page, url):
    require(page.d.current_url.startswith("file://"), f"the page is not a file:// URL: {page.d.current_url}")
    deadline, state = time.time() + 10, None
    while time.time() < deadline:
        state = page.state()
        if state and state.get("loaded"):
            break
        time.sleep(0.1)
    error = page.js("const e = document.getElementById('error'); return e && !e.hidden ? e.textContent : '';")
    require(state and state.get("loaded"), f"the viewer did not draw its panels within 10 s (state {state}; {error})")
    require(not error, f"the page shows an error: {error}")
    pixels = page.all_pixels()
    flat = [n for n, p in pixels.items() if p["colours"] < 2]
    require(not flat, f"panels with uniform pixels: {flat} ({pixels})")
    ok("loaded from file:// and drew four panels",
       ", ".join(f"{n} {p['colours']} colours" for n, p in pixels.items()))


def check_variant_key(page, data):
    if len(data["variants"]) < 2:
        return skip("key 2 selects the second variant", "the study has one variant")
    before, pixels = page.state(), page.all_pixels()
    page.key("2")
    after, now = page.state(), page.all_pixels()
    require(before["variant"] == 0 and after["variant"] == 1, f"key 2: variant {before['variant']} -> {after['variant']}")
    require(now["variant"]["hash"] != pixels["variant"]["hash"], "key 2: the Variant canvas did not change")
    require(now["reference"]["hash"] == pixels["reference"]["hash"], "key 2: the Reference canvas changed")
    ok("key 2 selects the second variant", f"{after['variantLabel']}; Variant canvas changed, Reference unchanged")


def check_spp_keys(page, data):
    if len(data["spp"]) < 2:
        return skip("Right/Left arrows step the spp", "the study has one sample count")
    from selenium.webdriver.common.keys import Keys
    start, pixels = page.state(), page.pixels("variant")
    page.key(Keys.ARROW_RIGHT)
    right, moved = page.state(), page.pixels("variant")
    page.key(Keys.ARROW_LEFT)
    left, back = page.state(), page.pixels("variant")
    require(right["spp"] == data["spp"][1] and left["spp"] == start["spp"] == data["spp"][0],
            f"arrows: spp {start['spp']} -> Right {right['spp']} -> Left {left['spp']}")
    require(moved["hash"] != pixels["hash"] and back["hash"] == pixels["hash"],
            "arrows: the Variant canvas did not follow the spp")
    ok("Right/Left arrows step the spp", f"{start['spp']} -> {right['spp']} -> {left['spp']}")


def set_exposure(page, stops):
    page.js("const s = document.getElementById('exposure'); s.value = String(arguments[0]);"
            "s.dispatchEvent(new Event('input', {bubbles: true}));", stops)


def check_exposure(page):
    pixels = page.all_pixels()
    set_exposure(page, 2)
    state, now = page.state(), page.all_pixels()
    require(abs(state["exposure"] - 2) < 1e-9, f"exposure slider: state exposure {state['exposure']}, expected 2")
    require(now["variant"]["hash"] != pixels["variant"]["hash"], "exposure slider: the Variant canvas did not change")
    require(now["reference"]["hash"] != pixels["reference"]["hash"], "exposure slider: the Reference canvas did not change")
    require(now["error"]["hash"] == pixels["error"]["hash"] and now["flip"]["hash"] == pixels["flip"]["hash"],
            "exposure slider: the error or FLIP panel changed")
    set_exposure(page, 0)
    require(page.pixels("variant")["hash"] == pixels["variant"]["hash"], "exposure back to 0: a different Variant image")
    ok("exposure slider changes Reference and Variant", "+2 stops: both changed; error and FLIP unchanged; 0 restores")


def check_zoom(page):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin
    before, drawn = page.state(), page.drawn()
    ActionChains(page.d).scroll_from_origin(ScrollOrigin.from_element(page.canvas("flip")), 0, -100).perform()
    after = page.state()
    require(after["zoom"] > before["zoom"] * 1.05, f"wheel zoom: zoom {before['zoom']:.3f} -> {after['zoom']:.3f}")
    redrawn = page.drawn()
    require(all(redrawn[n] > drawn[n] for n in PANELS), f"wheel zoom: not every panel redrew ({drawn} -> {redrawn})")
    centre, _ = same_view(page, "wheel zoom")
    ok("wheel zoom on the FLIP panel zooms all four",
       f"zoom {before['zoom']:.2f} -> {after['zoom']:.2f}; every panel shows image pixel {centre} at its centre")


def check_pan(page):
    from selenium.webdriver.common.action_chains import ActionChains
    before, (centre0, _) = page.state(), same_view(page, "before the drag")
    ActionChains(page.d).move_to_element(page.canvas("variant")).click_and_hold() \
        .move_by_offset(30, 20).move_by_offset(30, 25).release().perform()
    after = page.state()
    dx, dy = after["panX"] - before["panX"], after["panY"] - before["panY"]
    require(abs(dx - 60) < 1.5 and abs(dy - 45) < 1.5, f"drag by (60, 45): the view panned by ({dx:.1f}, {dy:.1f})")
    centre, opaque = same_view(page, "drag")
    require(centre != centre0, f"drag: the image pixel at the centre stayed {centre}")
    ok("drag on the Variant panel pans all four",
       f"panned ({dx:.0f}, {dy:.0f}); centre pixel {centre0} -> {centre}; same drawn region in every panel "
       f"({opaque} opaque canvas pixels)")


def check_readout(page):
    from selenium.webdriver.common.action_chains import ActionChains
    ActionChains(page.d).move_to_element(page.canvas("reference")).perform()
    w, h = page.size("reference")
    x, y = page.pixel_at("reference", w / 2, h / 2)
    text = page.js("return document.getElementById('readout').textContent;")
    require(text.startswith(f"pixel {x}, {y} ") and "reference" in text and ("variant" in text),
            f"hover read-out: expected pixel {x}, {y} with reference and variant values, got {text!r}")
    ok("hover read-out", text)


def check_reset(page, initial):
    page.key("0")
    state = page.state()
    same = all(abs(state[k] - initial[k]) < 1e-6 for k in ("zoom", "panX", "panY"))
    require(same, f"key 0: the view is {state}, expected the initial {initial}")
    same_view(page, "key 0")
    ok("key 0 resets the view", f"zoom {state['zoom']:.2f}, pan ({state['panX']:.1f}, {state['panY']:.1f})")


def check_table_sort(page, data):
    from selenium.webdriver.common.by import By
    tables = data.get("tables") or []
    numeric = [(t, c) for t, table in enumerate(tables) for c in range(1, len(table["columns"]))
               if any(isinstance((row[c] if c < len(row) else {}).get("value"), (int, float)) for row in table["rows"])]
    if not numeric:
        return skip("table header click sorts", "no table with a numeric column")
    t, c = numeric[0]
    table = tables[t]
    element = page.d.find_elements(By.CSS_SELECTOR, "#tables table")[t]

    def first_column():
        return [td.text for td in element.find_elements(By.CSS_SELECTOR, "tbody tr td:first-child")]

    def expected(descending):
        values = [row[c].get("value") if c < len(row) else None for row in table["rows"]]
        order = sorted(range(len(values)), key=lambda i: (values[i] is None,
                       0 if values[i] is None else (-values[i] if descending else values[i]), i))
        return [original[i] for i in order]

    original = first_column()
    header = element.find_elements(By.CSS_SELECTOR, "thead th")[c]
    header.click()
    ascending = first_column()
    require(ascending == expected(False), f"sort by {table['columns'][c]!r}: rows {ascending}, expected {expected(False)}")
    header.click()
    descending = first_column()
    require(descending == expected(True), f"sort again (reversed): rows {descending}, expected {expected(True)}")
    require(ascending != original or descending != original, f"sorting never changed the row order {original}")
    ok("table header click sorts", f"{table['columns'][c]!r}: {original} -> {ascending} -> {descending}")


def check_missing(page, data):
    missing = [(v, s) for v, variant in enumerate(data["variants"][:9]) for s, e in enumerate(variant["images"]) if e is None]
    if not missing:
        return skip("an unrendered entry shows a placeholder", "every variant is rendered at every spp")
    from selenium.webdriver.common.keys import Keys
    v, s = missing[0]
    page.key(str(v + 1))
    for _ in range(len(data["spp"])):
        page.key(Keys.ARROW_LEFT)
    for _ in range(s):
        page.key(Keys.ARROW_RIGHT)
    state = page.state()
    require(state["variant"] == v and state["spp"] == data["spp"][s], f"could not select the unrendered entry: {state}")
    stats = page.js("return document.getElementById('stats').textContent;")
    require("not rendered" in stats, f"unrendered entry: the statistics line says {stats!r}")
    pixels = page.pixels("variant")  # only the placeholder's text is opaque
    require(pixels["opaque"] < 0.05 * pixels["pixels"], "unrendered entry: the Variant panel still shows an image")
    ok("an unrendered entry shows a placeholder", f"{state['variantLabel']} at {state['spp']} spp")
    page.key("1")
    for _ in range(len(data["spp"])):
        page.key(Keys.ARROW_LEFT)


def screenshot(page, path):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin
    page.d.set_window_size(1400, 1000)
    time.sleep(0.2)
    set_exposure(page, 0)
    page.key("0")
    if len(page.data()["variants"]) > 1:
        page.key("2")
    ActionChains(page.d).scroll_from_origin(ScrollOrigin.from_element(page.canvas("variant")), 0, -60).perform()
    page.d.execute_script("window.scrollTo(0, 0);")  # the table checks scrolled down
    ActionChains(page.d).move_to_element_with_offset(page.canvas("variant"), 20, 10).perform()  # a read-out
    require(page.d.save_screenshot(path), f"could not save the screenshot {path}")
    ok("screenshot", path)


def check_network(page):
    urls, browser_ui = [], 0
    for entry in page.d.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        params = message.get("params", {})
        if params.get("documentURL", "").startswith(("chrome://", "chrome-untrusted://")):
            browser_ui += 1  # Chromium's own start-up pages (new tab page), not the report
        elif message.get("method") == "Network.requestWillBeSent":
            urls.append(params["request"]["url"])
        elif message.get("method") == "Network.webSocketCreated":
            urls.append(params["url"])
    require(urls, "the performance log holds no Network.requestWillBeSent event (is network logging on?)")
    bad = [u[:120] for u in urls if not u.startswith(("file://", "data:"))]
    require(not bad, f"the page requested non-local URLs: {bad}")
    resources = page.js("return performance.getEntriesByType('resource').map(e => e.name);")
    web = [r[:120] for r in resources if r.startswith(("http:", "https:", "ws:", "wss:"))]
    require(not web, f"performance resource entries over the network: {web}")
    kinds = sorted({u.split(":", 1)[0] for u in urls})
    ok("no network request", f"{len(urls)} requests, schemes {kinds}; {len(resources)} resource entries, none http(s)"
       + (f" ({browser_ui} events of Chromium's own pages ignored)" if browser_ui else ""))


def check_console(page):
    logs = page.d.get_log("browser")
    severe = [e["message"] for e in logs if e.get("level") == "SEVERE"]
    require(not severe, "JS errors in the console: " + " | ".join(severe))
    ok("no errors in the browser console", f"{len(logs)} console entries, none SEVERE")


def start_browser(profile):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in FLAGS + [f"--user-data-dir={profile}"]:
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"performance": "ALL", "browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(30)
    driver.set_script_timeout(30)
    driver.set_window_size(1400, 1000)
    return driver


def run(report, shot):
    try:
        page = Page(start_browser(PROFILE))
    except Exception as error:  # e.g. a chromedriver of another version than chromium
        print(f"FAIL  could not start {CHROMIUM} through {CHROMEDRIVER}: {type(error).__name__}: {error}".strip())
        return 1
    try:
        page.d.get_log("performance")  # drop the events of the start-up tab (chrome:// pages), before the report
        page.d.get("file://" + os.path.abspath(report))
        check_loaded(page, report)
        data = page.data()
        initial = page.state()
        check_variant_key(page, data)
        check_spp_keys(page, data)
        check_exposure(page)
        check_zoom(page)
        check_pan(page)
        check_readout(page)
        check_reset(page, initial)
        check_table_sort(page, data)
        check_missing(page, data)
        if shot:
            screenshot(page, shot)
        check_network(page)
        check_console(page)
    except Exception as failure:  # a failed check, or the driver's error (a timeout, an element not found)
        message = str(failure) if isinstance(failure, CheckFailed) else f"{type(failure).__name__}: {failure}".strip()
        print(f"FAIL  {message}", flush=True)
        try:
            for e in page.d.get_log("browser"):
                print(f"      console {e.get('level')}: {e.get('message')}")
        except Exception:
            pass
        return 1
    finally:
        page.d.quit()
    print("all checks passed")
    return 0


PROFILE = None


def main():
    global PROFILE
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--report", help="a study's report.html")
    source.add_argument("--mock", metavar="TEMPLATE", help="the viewer template, filled by mock_report.py (with --null)")
    parser.add_argument("--screenshot", metavar="PNG", help="save a 1400x1000 screenshot here")
    args = parser.parse_args()

    missing = [p for p in (CHROMIUM, CHROMEDRIVER) if not os.access(p, os.X_OK)]
    if importlib.util.find_spec("selenium") is None:
        missing.append("the Python module selenium (python3-selenium)")
    if missing:
        print(f"FAIL  missing {', '.join(missing)}: `bash scripts/setup.sh` installs them "
              "(Debian packages chromium, chromium-driver, python3-selenium)", flush=True)
        return 1

    work = tempfile.mkdtemp(prefix="symphong-browser-")
    PROFILE = os.path.join(work, "profile")
    os.mkdir(PROFILE)
    try:
        report = args.report
        if args.mock:
            report = os.path.join(work, "report.html")
            subprocess.run([sys.executable, os.path.join(HERE, "mock_report.py"), args.mock, report, "--null"], check=True)
            ok("mock report written", report)
        if not os.path.isfile(report):
            print(f"FAIL  no report at {report}")
            return 1
        return run(report, args.screenshot and os.path.abspath(args.screenshot))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
