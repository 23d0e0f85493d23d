"""A contact counts as reaching the limit overlap ``D`` in a band below it that holds
positions (core/deformable/state.py ``limit_band``), however small ``D`` is next to the
clearance."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from core.deformable.law import LIMIT_MARGIN

ROOT = Path(__file__).resolve().parents[2]

#: The solve runs in a child process so that a solve that never ends fails the test (at the
#: timeout) instead of hanging it; the fixed solve takes milliseconds after the import.
HANG_TIMEOUT_S = 120.0

SOLVE = """
import json, sys
from core import HystereticStop, Oscillator, simulate
xb, d = float(sys.argv[1]), float(sys.argv[2])
stop = HystereticStop(clearance=xb, limit_overlap=d)
res = simulate(Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1, u_s=1.0), stop, t_end=80.0)
print(json.dumps({"status": res.status.value, "peak": float(res.x_max) - xb}))
"""


@pytest.mark.parametrize("d", [1e-11, 3e-12, 1e-12])
def test_a_limit_overlap_a_few_hundred_positions_wide_ends_at_the_limit(d):
    """Regression: README's oscillator on a stop at clearance 0.24 with D = 1e-12 or 1e-11
    spun in the contact's steps for ever (3e-12 ended in a stick, as it still does). For
    D = 1e-12 the band ``LIMIT_MARGIN D`` (1e-18) lay between two positions 2.8e-17 apart:
    a step into it ended past ``D`` and was rejected, the step cut to a fifth ended where
    it began, and grew back. Now each ends at the limit overlap with its peak in the band
    (as D = 1e-9 did)."""
    out = subprocess.run(
        [sys.executable, "-c", SOLVE, "0.24", repr(d)], cwd=ROOT, capture_output=True,
        text=True, timeout=HANG_TIMEOUT_S, check=True,
    )
    got = json.loads(out.stdout)
    assert got["status"] == "limit_overlap"
    from core.deformable.state import limit_band  # (imported here: absent before the band)

    # the peak is a position: the band's bottom to within one spacing (a stick inside the
    # contact ends at the position nearest clearance + d_max)
    assert limit_band(0.24, d) - math.ulp(0.24) <= got["peak"] < d


@pytest.mark.parametrize("clearance", [0.0, 0.24, -3.0, 1e6])
@pytest.mark.parametrize("d", [1e-300, 1e-15, 1e-12, 1e-9, 0.05, 1e3])
def test_the_band_holds_positions_or_is_empty(clearance, d):
    """The band ``(d_max, D)`` is the paper-wide ``LIMIT_MARGIN D`` where positions near the
    stop resolve it, and at least LIMIT_BAND_SPACINGS position spacings wide otherwise."""
    from core.deformable.state import LIMIT_BAND_SPACINGS, limit_band

    d_max = limit_band(clearance, d)
    spacing = math.ulp(abs(clearance) + d)
    assert d_max <= (1.0 - LIMIT_MARGIN) * d
    assert d - d_max >= LIMIT_BAND_SPACINGS * spacing
    if LIMIT_MARGIN * d >= 2.0 * LIMIT_BAND_SPACINGS * spacing:
        assert d_max == (1.0 - LIMIT_MARGIN) * d
