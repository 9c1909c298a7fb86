"""``report.html`` in a real browser: a run's page and a sweep's page are loaded by headless Chromium (Debian's
``chromium``; ``.ci/run`` installs it) with every host unresolvable, through the DevTools protocol on a pipe:
no console error, no exception and no request beyond the file itself; every plot rendered (plotly's SVG layers
and, for the 3D view, its WebGL canvas); a screenshot that is not blank. The pages' content — units, Bf to 3
decimals, links to the designs' hulls, plotly's bundle once, nothing fetched — is checked in the HTML."""

from __future__ import annotations

import json
import os
import queue
import re
import shutil
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from hullopt.report import OVERLAY_NAME, Hulls, plot_overlay, write_report
from hullopt.models import wigley

CHROMIUM = next((p for p in (shutil.which(n) for n in ("chromium", "chromium-browser")) if p), None)
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="no chromium on this machine (Debian: apt-get install "
                                                             "chromium; .ci/run installs it)")


def _wigley(B: float) -> tuple:
    """A Wigley hull (L 100 m, T 6.25 m, D 10 m) of beam ``B`` [m] on a coarse grid and its sectional-area
    curve in closed form, A(x) = (4/3)·b(x)·T with b the waterline half-breadth [m²]."""
    s = wigley(100.0, B, 6.25, 10.0, n=41, m=21)
    s = type(s)(np.asarray(s.x), np.asarray(s.yz), np.asarray(s.lpp))
    beam = (B / 2) * (1.0 - (2.0 * (s.x - 50.0) / 100.0) ** 2)
    return s, 4.0 / 3.0 * beam * 6.25


def _hulls(n_designs: int = 1) -> Hulls:
    parent, a0 = _wigley(10.0)
    designs = [(f"design {k}" if n_designs > 1 else "design", *_wigley(10.5 + 0.5 * k)) for k in range(n_designs)]
    return Hulls(6.25, parent, a0, designs)


FIT = {
    "kind": "minimise", "converged": True, "met": True, "iterations": 212, "max_violation": 0.31,
    "targets": {"cb": {"target": 0.48, "achieved": 0.48003, "error": 3e-5, "tolerance": 1e-4, "met": True},
                "volume": {"target": 2998.0, "achieved": 2998.6, "error": 2e-4, "tolerance": 5e-4, "met": True}},
    "objective": {"name": "mean_added_resistance", "value": 5856.81, "parent": 13453.2},
    "objectives": {"mean_added_resistance": {"parent": 13453.2, "design": 5856.81, "unit": "N"},
                   "wetted_surface": {"parent": 1487.6, "design": 1517.4, "unit": "m²"},
                   "unfairness": {"parent": 1.0, "design": 1.7, "unit": "-"}},
    "achieved": {"displacement": 3073200.0, "volume": 2998.2, "cb": 0.48, "lcb_pct": -1.5},
    "parent": {"displacement": 2844000.0, "volume": 2774.6, "cb": 0.4442, "lcb_pct": -7.1e-15},
    "limits": {"dwl_turns": {"parent": 0.0, "design": 0.4, "bound": "<= parent", "tolerance": 1e-3},
               "kmt": {"parent": -0.0098, "design": -0.002, "bound": ">= parent - 0.05", "tolerance": 1e-3}},
    "warnings": ["design.apex_move[0] component 1 = 1.49 is within 1 % of its bound ±1.5"],
    "history": {"iteration": "augmented-Lagrangian round",
                "series": {"objective / parent's": [1.0, 0.61, 0.48, 0.45, 0.44],
                           "max constraint violation |residual| / tolerance": [40.0, 6.0, 1.2, 0.5, 0.31]}},
}


def _sweep_report(n: int = 4) -> dict:
    bf = np.linspace(0.012, 0.028, n)
    return {"kind": "pareto", "converged": False, "met": False, "iterations": 400, "pareto_count": n - 2,
            "targets": {"cb": 0.444201, "volume": 2774.59},
            "objective": {"name": "calm_resistance", "measure": "mean_added_resistance"},
            "designs": [{"bf_target": float(b), "objective": 1.0e5 + 2e5 * b, "measure": 3.0e4 - 4e5 * b,
                         "met": k != 1, "pareto": k not in (1, n - 1), "params": {"apex_move_d": [[0.0, 0.0]]},
                         "particulars": {"cb": 0.4442, "volume": 2774.6, "wetted_surface": 1490.0 + k}}
                        for k, b in enumerate(bf)],
            "achieved": {"cb": 0.4442}, "parent": {"cb": 0.4442, "volume": 2774.6, "wetted_surface": 1487.6},
            "objectives": {k: {"parent": v, "designs": [v] * n, "unit": u} for k, v, u in
                           (("calm_resistance", 1.04e5, "N"), ("mean_added_resistance", 2.2e4, "N"),
                            ("bf", 0.0213, "-"))}}


def _folder(tmp: Path, report: dict) -> Path:
    tmp.mkdir(parents=True, exist_ok=True)
    (tmp / "report.json").write_text(json.dumps(report))
    (tmp / "config.json").write_text("{}")
    return tmp


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> dict[str, Path]:
    """A minimise run's folder and a sweep's (design 2's hull file present), each with its report.html."""
    root = tmp_path_factory.mktemp("report")
    run = _folder(root / "run", FIT)
    h = _hulls()
    plot_overlay(h.parent, h.designs[0][1], 6.25, run / OVERLAY_NAME)
    write_report(run, FIT, h)
    sweep = _folder(root / "sweep", _sweep_report())
    (sweep / "designs" / "2").mkdir(parents=True)
    (sweep / "designs" / "2" / "hull.stl").write_bytes(b"solid x\nendsolid x\n")
    write_report(sweep, _sweep_report(), _hulls(2))
    return {"run": run / "report.html", "sweep": sweep / "report.html"}


# ----------------------------------------------------------------------------------------------- the HTML


def test_the_page_is_self_contained_with_plotly_once(pages):
    from plotly.offline import get_plotlyjs

    for page in pages.values():
        text = page.read_text(encoding="utf-8")
        assert text.count(get_plotlyjs()[:200]) == 1  # the bundle, embedded once
        # nothing to fetch: no script/link/img/iframe source, no CSS import or url() outside the page
        assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)\s*=\s*[\"'](?!data:)", text)
        assert not re.search(r"@import|url\(\s*['\"]?(https?:)?//", text)


def test_a_run_page_shows_units_targets_objectives_warnings_and_convergence(pages):
    text = pages["run"].read_text(encoding="utf-8")
    for part in ("Hulls in 3D", "Body plan", "Sectional-area curve", "Targets and constraints", "Convergence",
                 "Warnings", "within 1 % of its bound", "Displacement Δ [t]", "mean added resistance R_AW",
                 "Wetted surface S", "LCB from midship [% Lpp]", "max constraint violation"):
        assert part in text, part
    # R_AW parent → design in kN (its unit in a column), the change and relative change; round-off noise as 0
    row = re.search(r"mean added resistance R_AW</b></td>(.*?)</tr>", text).group(1)
    assert re.findall(r"<td>([^<]*)</td>", row) == ["kN", "13.453", "5.857", "-7.596", "-56.47"]
    assert "<th>unit</th>" in text
    assert "e-15" not in text.split("<body>")[1]
    # the design against its parent, embedded; the local limits, the violated one marked
    assert "Designs against the parent" in text and 'src="data:image/png;base64,iVBOR' in text
    row = re.search(r"<td>dwl_turns</td>(.*?)</tr>", text).group(1)
    assert "&lt;= parent" in row and "+0.4 ✗" in row
    assert "✗" not in re.search(r"<td>kmt</td>(.*?)</tr>", text).group(1)


def test_a_sweep_page_shows_the_front_with_bf_to_4_digits_and_links_to_hulls(pages):
    text = pages["sweep"].read_text(encoding="utf-8")
    assert "Pareto front" in text and "R_AW [kN]" in text and "R_T [kN]" in text
    for b in np.linspace(0.012, 0.028, 4):
        assert f"Bf target {b:.4g}" in text  # the hover text of each design
    assert '<a href="designs/2/hull.stl">' in text and "designs/0/hull.stl" not in text
    assert "1 of 4 designs miss their targets" in text
    assert re.search(r"parent: Bf 0\.0213(?!\d)", text)  # the parent's point beside the front
    # the designs' particulars beside the parent's (designs 0, 2 on the front, 3 and 4 off it)
    assert re.search(r"<th>particular</th><th>parent</th><th>design 0</th><th>design 2</th></tr>", text)
    assert "Wetted surface S [m²]" in text


def test_report_command_rebuilds_the_hulls_from_the_run_folder(cli, tmp_path):
    """``hullopt report`` on a fit's folder (config, kept parent and report; no solve): the hulls rebuilt from
    the parameters — the parent's sectional-area curve integrates to the Wigley's closed-form volume
    ∇ = (4/9)·L·B·T (the library's feature-curve Wigley, trapezoid over 41 stations: measured 0.18 % below);
    the design's is moved aft."""
    from hullopt.study import load_config
    from hullopt.study import run_parent
    from hullopt.report import read_run, run_hulls
    from hullopt.models import save_features

    folder = tmp_path / "run"
    folder.mkdir()
    _, raw = load_config(Path(__file__).resolve().parents[1] / "configs" / "fit_cb_lcb.toml")
    (folder / "config.json").write_text(json.dumps(raw))
    save_features(run_parent("wigley"), folder / "parent.json")
    params = {"apex_move_d": [[0.5, -0.3], [0.0, 0.0]], "distribution_c": [[0.2, -0.1]], "contour_edit_amplitude": []}
    (folder / "report.json").write_text(json.dumps({k: v for k, v in FIT.items() if k != "objectives"} | {
        "kind": "fit", "params": params}))
    code, out, err = cli("report", str(folder))
    assert code == 0, err
    assert "report.html" in out and (folder / "report.html").stat().st_size > 1e6
    h = run_hulls(folder, read_run(folder)[1])
    (name, design, areas), = h.designs
    volume = np.trapezoid(h.parent_areas, h.parent.x)
    assert volume == pytest.approx(4 / 9 * 100 * 10 * 6.25, rel=3e-3)
    # the frames slid aft (distribution c = 0.2): the design's centre of buoyancy 1.2 m aft of midship
    lcb = np.trapezoid(areas * design.x, design.x) / np.trapezoid(areas, design.x)
    assert name == "design" and lcb < 49.5 and np.max(np.abs(areas - h.parent_areas)) > 1.0
    code, _, err = cli("report", str(tmp_path / "nothing"))
    assert code == 2 and "is not a run folder" in err and err.count("\n") == 1


# ----------------------------------------------------------------------------------------------- Chromium


class Browser:
    """Headless Chromium driven over the DevTools protocol on a pipe (fds 3 and 4: JSON messages ended by a
    NUL byte), every host unresolvable."""

    def __init__(self, profile: Path):
        to_r, self._to = os.pipe()
        self._from, from_w = os.pipe()
        args = ["--headless", "--remote-debugging-pipe", "--no-sandbox", f"--user-data-dir={profile}",
                "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--disable-sync",
                "--disable-background-networking", "--disable-component-update", "--hide-scrollbars",
                "--host-resolver-rules=MAP * ~NOTFOUND", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                "about:blank"]
        self.proc = subprocess.Popen(["bash", "-c", f'exec "$0" "$@" 3<&{to_r} 4>&{from_w}', CHROMIUM, *args],
                                     pass_fds=(to_r, from_w), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_r)
        os.close(from_w)
        self._id, self.events, self._replies = 0, [], queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Runtime", "Log", "Network", "Page"):
            self.call(f"{domain}.enable", session=True)

    def _read(self):
        buf = b""
        while chunk := os.read(self._from, 1 << 16):
            buf += chunk
            *msgs, buf = buf.split(b"\0")
            for m in msgs:
                msg = json.loads(m)
                (self._replies.put if "id" in msg else self.events.append)(msg)

    def call(self, method: str, session: bool = False, timeout: float = 60.0, **params):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params}
        if session:
            msg["sessionId"] = self.session
        os.write(self._to, json.dumps(msg).encode() + b"\0")
        end = time.monotonic() + timeout
        while True:
            reply = self._replies.get(timeout=max(end - time.monotonic(), 0.01))
            if reply["id"] == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def evaluate(self, expression: str, timeout: float = 60.0):
        r = self.call("Runtime.evaluate", session=True, timeout=timeout, expression=expression, awaitPromise=True,
                      returnByValue=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def load(self, url: str, width: int = 1280, height: int = 2600) -> None:
        self.events.clear()
        self.call("Emulation.setDeviceMetricsOverride", session=True, width=width, height=height,
                  deviceScaleFactor=1, mobile=False)
        self.call("Page.navigate", session=True, url=url)
        end = time.monotonic() + 60
        while not any(e.get("method") == "Page.loadEventFired" for e in self.events):
            assert time.monotonic() < end, "the page did not finish loading in 60 s"
            time.sleep(0.05)

    def problems(self) -> list[str]:
        """Console errors and assertions, uncaught exceptions, browser log errors, and requests for anything
        but the page itself (file:, data:, blob:)."""
        out = []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.consoleAPICalled" and p["type"] in ("error", "assert"):
                out.append("console: " + " ".join(str(a.get("value", a.get("description"))) for a in p["args"]))
            elif m == "Runtime.exceptionThrown":
                out.append("exception: " + json.dumps(p["exceptionDetails"])[:500])
            elif m == "Log.entryAdded" and p["entry"]["level"] == "error":
                out.append(f"log: {p['entry']['text']} ({p['entry'].get('url', '')})")
            elif m == "Network.requestWillBeSent" and not p["request"]["url"].startswith(("file:", "data:", "blob:")):
                out.append(f"request: {p['request']['url']}")
        return out

    def screenshot(self, path: Path) -> Path:
        import base64

        path.write_bytes(base64.b64decode(self.call("Page.captureScreenshot", session=True, format="png")["data"]))
        return path

    def close(self) -> None:
        try:
            self.call("Browser.close", timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to)


# what the page looks like once plotly has drawn: per plot div, its SVG layers, WebGL canvases (3D) and size
RENDERED = """(async () => {
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  const out = {};
  for (const d of document.querySelectorAll('.js-plotly-plot')) {
    const r = d.getBoundingClientRect();
    const gl = d.querySelector('.gl-container canvas');
    out[d.id] = {svg: d.querySelectorAll('.main-svg').length,
                 traces: d.querySelectorAll('.trace, .scatterlayer path').length,
                 gl: gl ? gl.width * gl.height : 0,
                 webgl: gl ? !!(gl.getContext('webgl') || gl.getContext('experimental-webgl')) : null,
                 box: [r.left, r.top + window.scrollY, r.width, r.height]};
  }
  return out;
})()"""


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    if CHROMIUM is None:
        pytest.skip("no chromium on this machine (Debian: apt-get install chromium; .ci/run installs it)")
    b = Browser(tmp_path_factory.mktemp("chromium-profile"))
    yield b
    b.close()


def _not_blank(png: Path, box=None) -> tuple[float, float]:
    """(fraction of pixels that are not background, mean RGB standard deviation) of a screenshot or of the
    region ``box`` = [left, top, width, height] [px] in it."""
    from skimage.io import imread

    img = imread(png)[..., :3].astype(float)
    if box is not None:
        x, y, w, h = (int(round(v)) for v in box)
        img = img[max(y, 0):y + h, max(x, 0):x + w]
    ink = np.any(np.abs(img - img[0, 0]) > 24, axis=-1).mean()
    return float(ink), float(img.reshape(-1, 3).std(axis=0).mean())


@needs_chromium
@pytest.mark.parametrize("name, plots", [("run", {"hull3d", "bodyplan", "sac", "convergence"}),
                                         ("sweep", {"pareto", "hull3d", "bodyplan", "sac"})])
def test_the_page_renders_in_headless_chromium_offline(browser, pages, name, plots, tmp_path):
    page = pages[name]
    browser.load(page.as_uri())
    height = browser.evaluate("document.documentElement.scrollHeight")
    browser.call("Emulation.setDeviceMetricsOverride", session=True, width=1280, height=min(height, 8000),
                 deviceScaleFactor=1, mobile=False)  # the whole page in the screenshot
    rendered = browser.evaluate(RENDERED)
    problems = browser.problems()
    png = browser.screenshot(tmp_path / f"{name}.png")
    shutil.copy(png, page.with_suffix(".png"))  # beside the page, for a person to look at
    assert problems == [], problems
    assert set(rendered) == plots, rendered
    for div, r in rendered.items():
        assert r["svg"] >= 2 and r["box"][2] > 300 and r["box"][3] > 200, (div, r)
        assert r["traces"] >= 1 if div != "hull3d" else r["gl"] > 0, (div, r)  # SVG traces, or 3D in WebGL
    assert rendered["hull3d"]["gl"] > 0 and rendered["hull3d"]["webgl"], rendered["hull3d"]
    ink, spread = _not_blank(png)
    assert ink > 0.02 and spread > 10, (ink, spread)  # a blank page: 0 and 0
    # the 3D view itself is drawn (WebGL through SwiftShader), not an empty box: the hull's blue fills a
    # good part of it
    box = rendered["hull3d"]["box"]
    ink3d, _ = _not_blank(png, [box[0], box[1] + 60, box[2], box[3] - 60])
    assert ink3d > 0.05, ink3d


@needs_chromium
def test_the_browser_check_sees_console_errors_exceptions_and_requests(browser, tmp_path):
    """The check itself: a page that logs an error, throws and fetches from the network fails it."""
    page = tmp_path / "bad.html"
    page.write_text('<!DOCTYPE html><html><head><script>console.error("broken"); null.x;</script></head><body>'
                    '<img src="https://example.com/x.png"></body></html>')
    browser.load(page.as_uri())
    browser.evaluate("new Promise(r => setTimeout(r, 200))")
    found = "\n".join(browser.problems())
    assert "console: broken" in found and "exception:" in found and "request: https://example.com/x.png" in found, found
