"""The CSV downloads in the browser: files named after the scene and its parameters, units
in the column names, and a transitions file with the impacts' speeds and impulses."""

from __future__ import annotations

import re

import pytest
from uipage import Page

pytestmark = pytest.mark.ui


def _download(p: Page, css: str) -> tuple[str, list[str]]:
    with p.page.expect_download(timeout=30_000) as info:
        p.page.locator(f"{css} button, {css} a").first.click()
    download = info.value
    return download.suggested_filename, open(download.path()).read().splitlines()


def test_downloads_name_the_run_and_its_units(browser, server, shots):
    p = Page(browser, server + "?scene=7c&units=SI&L=0.01")
    try:
        name, lines = _download(p, ".fie-download")
        # In SI units the name says so, with m, k and L (app/export.py).
        assert re.fullmatch(
            r"fie_7c_trajectory_SI_m-0.5_k-200_L-10mm_stop-rigid_[A-Za-z0-9._-]+\.csv", name)
        assert "r-0.3" in name
        assert lines[2].startswith("t [s],x [mm],xdot [m/s],mode,contact_force [N]")
        name, lines = _download(p, ".fie-download-transitions")
        assert re.fullmatch(
            r"fie_7c_transitions_SI_m-0.5_k-200_L-10mm_stop-rigid_[A-Za-z0-9._-]+\.csv", name)
        assert lines[2].startswith("t [s],kind,x [mm],v_before [m/s],v_after [m/s]")
        impacts = [row.split(",") for row in lines[3:] if ",impact," in row]
        assert len(impacts) > 3
        # Newton's law with r = 0.3 (scene 7c), to rounding: v_after = -r v_before.
        for row in impacts:
            assert float(row[4]) == pytest.approx(-0.3 * float(row[3]), rel=1e-12)
            assert float(row[6]) > 0
        p.page.screenshot(path=shots / "exports.png")
        assert p.errors == []
    finally:
        p.close()
