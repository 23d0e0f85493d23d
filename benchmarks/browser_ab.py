"""A/B of slider-release latency: this checkout against a git revision, in one browser.

On a shared machine the latency of ``browser_latency.py`` drifts by 20-30 ms between runs,
more than most single changes are worth. This harness serves both versions at once (two
``panel serve`` processes), opens one page of each in the same Chromium, and alternates
releases between them (A B, B A, ...), so that both see the same load. It prints the median
and 95th percentile of each and the median of the paired differences, of the whole latency
and of the browser's part (from the full solution's arrival to the picture shown). The probe
and the drag are those of ``browser_latency.py``.

Usage: ``.venv/bin/python benchmarks/browser_ab.py --ref HEAD~1 [--scenes 5b,7c] [--rounds 40]``
(the revision is checked out into a temporary git worktree, removed afterwards), or
``--patches``: this checkout with its perf patches (``app/perf``, ``static/perf``) on (A)
and off (B). The releases alternate between two values, so from the third on the answer is
cached and the drawing is measured; with ``--fresh`` every release lands on a new value and
its solve is measured too.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import browser_latency as bl  # noqa: E402

ROOT = bl.ROOT


def compare(browser, urls: dict[str, str], scene: str, rounds: int, fresh: bool = False
            ) -> dict[str, dict[str, np.ndarray]]:
    """The probe's records (``browser_latency.results``: latencies [ms] in ``painted``) of
    ``rounds`` releases per version, alternating between them."""
    pages = {}
    for key, url in urls.items():
        pages[key] = browser.new_page(viewport={"width": 1600, "height": 2000})
        bl.open_scene(pages[key], url, scene)
    order = list(pages)
    for r in range(rounds):
        for key in (order if r % 2 == 0 else order[::-1]):
            pages[key].bring_to_front()
            bl.drag(pages[key], r, fresh=fresh)
    lat = {key: bl.results(page) for key, page in pages.items()}
    for page in pages.values():
        page.close()
    return lat


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    target = parser.add_mutually_exclusive_group(required=True)
    target.add_argument("--ref", help="git revision to compare against (B)")
    target.add_argument("--patches", action="store_true",
                        help="B = this checkout with the perf patches off")
    parser.add_argument("--base", help="git revision to serve as A instead of this checkout "
                        "(to find which change moved the latency)")
    parser.add_argument("--scenes", default="5b,7c")
    parser.add_argument("--rounds", type=int, default=40)
    parser.add_argument("--raw", action="store_true", help="print every latency")
    parser.add_argument("--fresh", action="store_true",
                        help="every release a new value (its solve measured too)")
    parser.add_argument("--ports", default="0,0",
                        help="server ports of A and B (default: free ones)")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp:
        other, base = Path(tmp) / "b", Path(tmp) / "a"
        trees = [(other, args.ref)] if not args.patches else []
        if args.base:
            trees.append((base, args.base))
        for tree, rev in trees:
            subprocess.run(["git", "worktree", "add", "--detach", "-q", str(tree), rev],
                           cwd=ROOT, check=True)
        procs = []
        try:
            port_a, port_b = (int(p) for p in args.ports.split(","))
            proc_a, url_a = bl.serve_explorer(base if args.base else ROOT, port=port_a)
            procs.append(proc_a)
            proc_b, url_b = (bl.serve_explorer(ROOT, patches=False, port=port_b)
                             if args.patches else bl.serve_explorer(other, port=port_b))
            procs.append(proc_b)
            b_is = "this checkout, perf patches off" if args.patches else args.ref
            a_is = args.base or "this checkout"
            print(f"A = {a_is}, B = {b_is}; {args.rounds} releases each, alternating")
            print(f"{'scene':>6} {'A median':>9} {'A p95':>7} {'B median':>9} {'B p95':>7} "
                  f"{'median(A-B)':>12} {'browser(A-B)':>13}")
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=bl.CHROMIUM,
                                             args=bl.CHROMIUM_ARGS)
                for scene in args.scenes.split(","):
                    rec = compare(browser, {"A": url_a, "B": url_b}, scene, args.rounds,
                                  args.fresh)
                    # A page that missed a release has fewer: pair the rounds both have.
                    n = min(len(rec["A"]["painted"]), len(rec["B"]["painted"]))
                    a, b = rec["A"]["painted"][:n], rec["B"]["painted"][:n]
                    # The browser's part: from the full solution's arrival to the picture
                    # shown, without the server's time, which varies most on a busy host.
                    pa = a - rec["A"]["arrived"][:n]
                    pb = b - rec["B"]["arrived"][:n]
                    # A release that changed nothing is NaN (browser_latency.drag).
                    print(f"{scene:>6} {np.nanmedian(a):>9.1f} {np.nanpercentile(a, 95):>7.1f} "
                          f"{np.nanmedian(b):>9.1f} {np.nanpercentile(b, 95):>7.1f} "
                          f"{np.nanmedian(a - b):>+12.1f} {np.nanmedian(pa - pb):>+13.1f}")
                    for key in ("A", "B"):
                        print(f"{'':>6} {key}: {bl.stage_line(rec[key])}")
                    if args.raw:
                        for key in ("A", "B"):
                            print(f"{'':>6} {key} ms: "
                                  + " ".join(f"{x:.0f}" for x in rec[key]["painted"]))
                browser.close()
        finally:
            for proc in procs:
                proc.terminate()
                proc.wait(timeout=10)
            for tree, _ in trees:
                subprocess.run(["git", "worktree", "remove", "--force", str(tree)], cwd=ROOT,
                               check=False)


if __name__ == "__main__":
    main()
