"""Server CPU of a new session's page, two source trees paired: build, attach, serialize.

Each round runs one process per tree, one after the other; a process builds a first page
(imports, caches), then ``--pages`` default pages as the server does (``app.main.create_app``
and ``app.main.serve`` into a fresh ``Document``) followed by the document's first
serialization (``Document.to_json``, what the browser's first pull gets), and reports the CPU
time of each (``time.process_time``). Alternating the trees spreads the load of a shared
machine over both.

    PYTHONPATH=. python benchmarks/page_pair.py /path/to/other/tree [--rounds 4] [--pages 12]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Run in each tree (its own ``app``): model count and CPU seconds per page.
PAGES = r"""
import importlib, json, sys, time
from bokeh.document import Document
from panel.io.state import set_curdoc
main = importlib.import_module("app.main")
def page():
    doc = Document()
    with set_curdoc(doc):
        main.serve(main.create_app(), doc)
    doc.to_json()
    return len(doc.models)
page()
cpu = []
for _ in range(int(sys.argv[1])):
    t0 = time.process_time()
    models = page()
    cpu.append(time.process_time() - t0)
print(json.dumps([models, cpu]))
"""


def run(tree: Path, pages: int) -> tuple[int, list[float]]:
    out = subprocess.run([sys.executable, "-c", PAGES, str(pages)], cwd=tree, check=True,
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": "."})
    models, cpu = json.loads(out.stdout.strip().splitlines()[-1])
    return models, cpu


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("other", type=Path, help="the other source tree (e.g. a checkout of main)")
    p.add_argument("--rounds", type=int, default=4)
    p.add_argument("--pages", type=int, default=12, help="pages per process")
    args = p.parse_args()
    trees = {"other": args.other.resolve(), "this": ROOT}
    cpu: dict[str, list[float]] = {k: [] for k in trees}
    models: dict[str, int] = {}
    for r in range(args.rounds):
        for name, tree in trees.items():
            models[name], pages = run(tree, args.pages)
            cpu[name] += pages
            print(f"round {r + 1} {name}: median {statistics.median(pages):.3f} s "
                  f"(load average {os.getloadavg()[0]:.1f})", flush=True)
    print("| tree | models | pages | cpu/page median [s] | p10 [s] | min [s] |")
    print("|---|---|---|---|---|---|")
    for name, values in cpu.items():
        values.sort()
        print(f"| {name} ({trees[name]}) | {models[name]} | {len(values)} | "
              f"{statistics.median(values):.3f} | {values[len(values) // 10]:.3f} | "
              f"{values[0]:.3f} |")


if __name__ == "__main__":
    main()
