"""Long runs of a scene: the horizon keeps the scene; the window over the run."""

from __future__ import annotations

import panel as pn
import pytest

from app.explorer import Explorer
from app.scenes import CUSTOM


def test_a_longer_horizon_keeps_the_scene(monkeypatch):
    """``?scene=5a&tend=5000`` and a horizon typed on scene 10 turned the page 'custom'
    (title and caption gone), though a long run of a figure is still that figure. The
    horizon keeps the scene, by widget and by link; a physical value still leaves it."""
    from panel.io.location import Location

    ex = Explorer()
    ex.scene_select.value = "10"
    ex.controls.commit({"t_end": 3000.0})
    assert ex.state.t_end == 3000.0 and ex.state.scene == "10"
    assert "Fig. 10" in ex.caption.object
    ex.controls.commit({"clearance": ex.state.clearance * 0.9})
    assert ex.state.scene == CUSTOM
    monkeypatch.setattr(pn.state, "_location", Location(search="?scene=5a&tend=5000"))
    linked = Explorer()
    linked.sync_url()
    assert (linked.state.scene, linked.state.t_end) == ("5a", pytest.approx(5000.0))
    assert not linked.alert.visible
