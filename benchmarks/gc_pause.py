"""Pause of a full garbage collection in the server process, with and without freezing.

Builds the explorer's page for 1, 5 and 15 sessions in this process (as ``panel serve``
does, each into its own Bokeh document), then times a full collection (``gc.collect()``):
once with every object tracked, as CPython leaves them, and once after the server's policy
(``app.memory``: live objects frozen once a page has loaded). A full collection runs by
itself now and then; while it runs the server answers nobody, so its length is added to
whatever slider release it lands in.

Usage: ``.venv/bin/python benchmarks/gc_pause.py [--repeat N]``
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bokeh.document import Document  # noqa: E402

from app.memory import freeze_live_objects  # noqa: E402

#: Numbers of sessions whose pages are built.
SESSIONS = (1, 5, 15)


def _create_app():
    """``app/main.py``'s page factory, without marking a page servable."""
    source = (ROOT / "app" / "main.py").read_text().replace(
        "create_app().servable(title=TITLE)", "")
    namespace = {"__file__": str(ROOT / "app" / "main.py"), "__name__": "fie_main"}
    exec(compile(source, "app/main.py", "exec"), namespace)  # noqa: S102 - our own module
    return namespace["create_app"]


def full_collection_ms(repeat: int) -> float:
    """Median wall time [ms] of ``gc.collect()``."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        gc.collect()
        times.append(1e3 * (time.perf_counter() - t0))
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    create_app = _create_app()
    docs = []
    print(f"{'sessions':>8} {'tracked objects':>16} {'full GC ms':>11} "
          f"{'frozen: tracked':>16} {'full GC ms':>11}")
    for n in SESSIONS:
        while len(docs) < n:
            doc = Document()
            create_app().server_doc(doc)
            docs.append(doc)
        gc.unfreeze()
        gc.collect()
        tracked = len(gc.get_objects())
        plain = full_collection_ms(args.repeat)
        freeze_live_objects()
        frozen_tracked = len(gc.get_objects())
        frozen = full_collection_ms(args.repeat)
        print(f"{n:>8} {tracked:>16,} {plain:>11.1f} {frozen_tracked:>16,} {frozen:>11.2f}")
    gc.unfreeze()


if __name__ == "__main__":
    main()
