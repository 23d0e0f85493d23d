"""Slider release -> repainted plot, measured in a real browser (Debian's Chromium).

Serves the explorer with ``panel serve`` on a free loopback port, opens a rigid-stop and a
hysteretic-stop scene, drags a slider many times and measures, inside the page, the time
from the ``pointerup`` that ends each drag until every figure has repainted with the full
solution (until the screen shows the frame with the last figure repaint, once the full
solution has arrived, as the page itself marks it, see ``app.explorer``).
Prints the median and 95th percentile per scene against the targets, how many
figure repaints a release cost, and the share of CPU time the host took from this machine
meanwhile (steal). A p95 rests on the few slowest releases: 100 moves (the default) put
five releases above it, 40 only two.

Usage: ``.venv/bin/python benchmarks/browser_latency.py [--moves N] [--scenes 5b,11]
[--slider mu_s]``
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app.scenes import SCENES  # noqa: E402
from app.solve.presets import PREVIEW_SAMPLES  # noqa: E402

CHROMIUM = os.environ.get("CHROMIUM", shutil.which("chromium") or "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
#: p95 targets [ms] by stop type.
TARGETS_MS = {"rigid": 100.0, "hysteretic": 250.0, "none": 100.0}
#: Slider dragged in each scene (``--slider``) and the drag distance [px] (alternating left
#: and right).
SLIDER = "clearance"
DRAG_PX = 12
#: A trajectory with more points than this is a full solve, not a preview: the probe's
#: last resort, for a page that marks a full solution neither with the model of class
#: ``fie-solution-arrived`` (app.explorer) nor in the trajectory's ``tags`` (older pages).
#: Previews are drawn from the exact motion per pixel column too, so on today's page a
#: preview can have more points than this (scene 10: 857).
FULL_MIN_POINTS = PREVIEW_SAMPLES + 50

#: A release whose full solution has not repainted after this long [ms] counts as missed.
RELEASE_TIMEOUT_MS = 20_000
#: Paints quieter than this [ms] after the full solution arrived end a measurement.
SETTLE_MS = 250
#: How often [ms] the harness asks the page whether a measurement has ended. The probe
#: times the release inside the page; Playwright's default (the question asked in every
#: animation frame) ran the harness's own script in the very frames being measured.
POLL_MS = 100

#: Installs the probe. It records the ``pointerup`` that ends a drag, notices when the full
#: solution arrives (the page's marker, not a preview), and then follows every figure
#: repaint (BokehJS ``PlotView._actual_paint``) until none has happened for ``settle`` ms:
#: the latency is from the ``pointerup`` until the screen shows the frame with the last
#: of those paints: the start of the following frame (the next vsync), i.e. until every
#: plot shows the new solution. A paint made in an animation-frame callback (where
#: BokehJS paints) is in that frame; one made in a task, in the next. It counts the
#: repaints of all figures, not only the one whose data arrived first, and it does not
#: poll.
JS_PROBE = """([minPoints, settle]) => {
  const doc = Bokeh.documents[0];
  const traj = [...doc.all_models].find(m => m.data && "mode" in m.data);
  const lat = (window.__lat = {up: null, painted: [], paints: [], pending: null,
                               sent: [], received: [], arrived: [], bytes: []});
  const ws = window.__fie_ws || {frames: [], sends: []};
  const STAGES = ["sent", "received", "arrived", "bytes"];
  document.addEventListener("pointerup", () => { lat.up = performance.now(); }, true);
  document.addEventListener("pointerdown", () => { lat.up = null; }, true);
  // ``waiting``: paints whose frame is not on screen yet. The measurement ends only when
  // none is: a paint late in the settle time used to have its frame shown after the end,
  // and that frame then ended a second measurement with no release (pending null), which
  // recorded the page's age (9-22 s) as a latency and shifted the following releases.
  let last = null, timer = null, waiting = 0;
  function finish() {
    if (lat.pending === null || waiting > 0) return;
    lat.painted.push(last - lat.pending);
    lat.paints.push(lat.count);
    for (const key of STAGES) lat[key].push(lat.stage[key]);
    lat.pending = null;
  }
  function mark() {
    waiting -= 1;
    if (lat.pending === null) return;
    last = performance.now();
    clearTimeout(timer);
    timer = setTimeout(finish, settle);
  }
  // Whether the code running now is an animation frame callback (BokehJS paints in them).
  let inFrame = false;
  const raf = window.requestAnimationFrame.bind(window);
  window.requestAnimationFrame = (cb) => raf((ts) => {
    inFrame = true;
    try { cb(ts); } finally { inFrame = false; }
  });
  function painted() {
    if (lat.pending === null) return;
    lat.count += 1;
    waiting += 1;
    // A paint made in a frame callback is in that frame, which the screen shows at the
    // next vsync: the start of the next frame. A paint made in a task is in the next frame,
    // shown at the start of the one after.
    if (inFrame) raf(mark);
    else raf(() => raf(mark));
  }
  const PlotView = Bokeh.require("models/plots/plot_canvas").PlotView.prototype;
  const paint = PlotView._actual_paint;
  PlotView._actual_paint = function (...args) {
    const out = paint.apply(this, args);
    painted();
    return out;
  };
  // The full solution's arrival: the page's own signal (the text of the model of class
  // fie-solution-arrived, set last in the full solution's message), else the trajectory's
  // tags (older pages), else a trajectory with more points than a preview.
  const marker = [...doc.all_models].find(
    m => Array.isArray(m.css_classes) && m.css_classes.includes("fie-solution-arrived"));
  const signal = marker != null ? marker.properties.text.change
    : "tags" in traj.properties && traj.tags.length ? traj.properties.tags.change : null;
  const full = () => signal !== null || traj.data.t.length >= minPoints;
  (signal ?? traj.properties.data.change).connect(() => {
    if (lat.up === null || !full()) return;
    lat.pending = lat.up;
    // Where the time went: the release's value sent, the last frame of the message that
    // brought the full solution received, and its data applied (all since the pointerup).
    const sent = ws.sends.find(t => t >= lat.up);
    const frames = ws.frames.filter(f => f[0] >= lat.up);
    lat.stage = {sent: sent === undefined ? NaN : sent - lat.up,
                 received: frames.length ? frames[frames.length - 1][0] - lat.up : NaN,
                 bytes: frames.reduce((n, f) => n + f[1], 0),
                 arrived: performance.now() - lat.up};
    ws.frames.length = 0;
    ws.sends.length = 0;
    lat.up = null;
    lat.count = 0;
    last = performance.now();
    painted();
  });
}"""

#: Installed before the page loads: the time and size of every websocket frame the page
#: receives, and the time of every frame it sends (the probe reads them at each release).
WS_PROBE = """(() => {
  const ws = (window.__fie_ws = {frames: [], sends: []});
  const Native = window.WebSocket;
  window.WebSocket = class extends Native {
    constructor(...args) {
      super(...args);
      this.addEventListener("message", (e) => {
        const d = e.data;
        ws.frames.push([performance.now(), typeof d === "string" ? d.length : d.byteLength]);
        if (ws.frames.length > 2000) ws.frames.splice(0, 1000);
      });
    }
    send(data) {
      ws.sends.push(performance.now());
      if (ws.sends.length > 2000) ws.sends.splice(0, 1000);
      return super.send(data);
    }
  };
})()"""


def cpu_times() -> tuple[int, int] | None:
    """(steal, total) CPU ticks of the machine so far (Linux ``/proc/stat``), else None.

    Steal is time the hypervisor gave this virtual machine's CPUs to others: on a shared
    host it, not the explorer, makes the tail of a run, so each run reports it.
    """
    try:
        with open("/proc/stat") as f:
            ticks = [int(v) for v in f.readline().split()[1:]]
    except (OSError, ValueError):
        return None
    return (ticks[7] if len(ticks) > 7 else 0), sum(ticks[:8])


def steal_percent(before: tuple[int, int] | None, after: tuple[int, int] | None) -> str:
    """The share of CPU time stolen between two :func:`cpu_times`, e.g. ``"3.2"``."""
    if before is None or after is None or after[1] <= before[1]:
        return "-"
    return f"{100.0 * (after[0] - before[0]) / (after[1] - before[1]):.1f}"


def serve_explorer(root: Path = ROOT, patches: bool = True,
                   port: int = 0) -> tuple[subprocess.Popen, str]:
    """``panel serve`` of the explorer in the checkout ``root`` on loopback ``port`` (0: a
    free one); with ``patches=False`` the perf patches are off (app.perf's switch in the
    server, and ``paint_shortcuts=off`` in the page's address)."""
    if not port:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
    proc = subprocess.Popen(
        [sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port),
         "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}",
         "--static-dirs", "assets=static", "--liveness"],
        cwd=root, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        env={**os.environ, "EXPLORER_PERF_PATCHES": "on" if patches else "off"},
    )
    for _ in range(300):
        try:
            urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2)
            query = "" if patches else "?paint_shortcuts=off"
            return proc, f"http://127.0.0.1:{port}/main{query}"
        except OSError:
            time.sleep(0.2)
    proc.kill()
    raise RuntimeError("panel serve did not start")


def open_scene(page, url: str, scene: str) -> None:
    """Load ``scene`` in ``page``, wait until BokehJS is idle and install the probe."""
    page.add_init_script(WS_PROBE)
    page.goto(f"{url}{'&' if '?' in url else '?'}scene={scene}", timeout=60_000)
    page.wait_for_function("() => window.Bokeh && Bokeh.documents.length > 0 && "
                           "Bokeh.documents[0].is_idle", timeout=60_000)
    page.evaluate(JS_PROBE, [FULL_MIN_POINTS, SETTLE_MS])


def drag(page, i: int, slider: str = SLIDER, fresh: bool = False) -> None:
    """The ``i``-th drag and release of the slider (alternately right and left), then wait
    for the probe's measurement of it (NaN if the release changed nothing). With ``fresh``
    each drag is a pixel longer than the last, so that every release lands on a value not
    solved before (else the releases alternate between two values, cached from the third
    on: the drawing is measured, not the solve)."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    box = page.locator(f".fie-w-{slider} .noUi-handle").first.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    length = DRAG_PX + (i if fresh else 0)
    dx = length if i % 2 == 0 else -length
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + dx, y, steps=4)
    page.mouse.up()
    try:
        page.wait_for_function(f"() => window.__lat.painted.length > {i}",
                               timeout=RELEASE_TIMEOUT_MS, polling=POLL_MS)
    except PlaywrightTimeout:  # the release changed nothing: count it as missed
        page.evaluate("() => { const lat = window.__lat; lat.painted.push(NaN); "
                      "lat.paints.push(0); lat.pending = null; "
                      "for (const k of ['sent', 'received', 'arrived', 'bytes']) "
                      "lat[k].push(NaN); }")


#: What the probe records of each release besides its latency (``painted``): since the
#: pointerup [ms], the release's value ``sent``, the last frame of the full solution's
#: message ``received``, its data ``arrived`` in the trajectory's source; the ``bytes``
#: the page received meanwhile; the figure ``paints``.
STAGES = ("sent", "received", "arrived", "bytes", "paints")


def results(page) -> dict[str, np.ndarray]:
    """The probe's records of ``page`` so far: ``painted`` and each of :data:`STAGES`."""
    lat = page.evaluate("() => window.__lat")
    return {key: np.asarray(lat[key], dtype=float) for key in ("painted", *STAGES)}


def stage_line(rec: dict[str, np.ndarray]) -> str:
    """Medians of where a release's time went: server (sent to received), browser before
    the data is in the source (decode and apply), paint (arrived to painted)."""
    med = {k: float(np.nanmedian(v)) if np.isfinite(v).any() else math.nan
           for k, v in rec.items()}
    return (f"send {med['sent']:.0f}, server+net {med['received'] - med['sent']:.0f}, "
            f"apply {med['arrived'] - med['received']:.0f}, "
            f"paint {med['painted'] - med['arrived']:.0f} ms; "
            f"{med['bytes'] / 1e3:.0f} kB, {med['paints']:.0f} paints")


def measure(page, url: str, scene: str, moves: int,
            slider: str = SLIDER) -> dict[str, np.ndarray]:
    """The probe's records (:func:`results`) of ``moves`` drags of ``slider`` in
    ``scene``."""
    open_scene(page, url, scene)
    for i in range(moves):
        drag(page, i, slider)
    return results(page)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--moves", type=int, default=100)
    parser.add_argument("--patches", choices=("on", "off"), default="on",
                        help="the perf patches (app/perf, static/perf)")
    parser.add_argument("--scenes", default="5b,7c,10,11")
    parser.add_argument("--port", type=int, default=0, help="server port (default: free)")
    parser.add_argument("--slider", default=SLIDER,
                        help="state parameter whose slider is dragged (default: clearance)")
    parser.add_argument("--json", help="also write every release's records to this file")
    args = parser.parse_args()
    records = {}
    from playwright.sync_api import sync_playwright

    proc, url = serve_explorer(patches=args.patches == "on", port=args.port)
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            page = browser.new_page(viewport={"width": 1600, "height": 2000})
            print(f"{'scene':>6} {'stop':>11} {'moves':>6} {'median ms':>10} {'p95 ms':>8} "
                  f"{'target':>7}  ok  {'paints':>6}  {'steal %':>7}")
            for scene in args.scenes.split(","):
                stop = SCENES[scene].values["stop_type"]
                before = cpu_times()
                rec = measure(page, url, scene, args.moves, args.slider)
                lat, paints = rec["painted"], rec["paints"]
                steal = steal_percent(before, cpu_times())
                missed = int(np.isnan(lat).sum())
                lat = lat[~np.isnan(lat)]
                med, p95 = np.median(lat), np.percentile(lat, 95)
                target = TARGETS_MS[stop]
                ok = "yes" if p95 < target else "NO "
                print(f"{scene:>6} {stop:>11} {len(lat):>6} {med:>10.1f} {p95:>8.1f} "
                      f"{target:>7.0f}  {ok}  {np.median(paints):>6.0f}  {steal:>7}"
                      + (f"  ({missed} releases missed)" if missed else ""))
                print(f"{'':>6} median: {stage_line(rec)}")
                records[scene] = {key: [None if math.isnan(x) else float(x) for x in val]
                                  for key, val in rec.items()}
            browser.close()
        if args.json:
            Path(args.json).write_text(json.dumps(records))
    finally:
        proc.terminate()
        proc.wait(timeout=10)


if __name__ == "__main__":
    main()
