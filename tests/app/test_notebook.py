"""docs/explorer.ipynb runs in a Jupyter kernel: the explorer and one of its parts display
with ``pn.extension()``, and the two figures it computes with ``core`` have the numbers of the
paper's closed forms (docs/physics.md, "Closed-form results")."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "docs" / "explorer.ipynb"
#: Seconds a cell may take (the explorer's first solve and Panel's first render).
CELL_TIMEOUT_S = 300
#: The exact solver's event times come from closed-form roots: its steady values agree with
#: the closed forms to rounding, far inside this.
REL = 1e-9

#: The paper's friction pair (the notebook's FRICTION): a = mu_k/u_s, b = mu_s/u_s.
A, B = 0.2, 0.3


@pytest.fixture(scope="module")
def executed():
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(NOTEBOOK, as_version=4)
    # Which tree the kernel imported, said at the end (not part of the notebook on disk).
    nb.cells.append(nbformat.v4.new_code_cell(
        "import app, core\nprint(app.__file__, core.__file__, sep='\\n')",
        metadata={"tags": ["imported-from"]}))
    # From the repository's root: the kernel imports this tree's core and app.
    NotebookClient(nb, timeout=CELL_TIMEOUT_S, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT)}}).execute()
    return nb


def _outputs(cell) -> list[dict]:
    return [dict(output) for output in cell.get("outputs", [])]


def test_the_kernel_ran_this_trees_code(executed):
    [cell] = [c for c in executed.cells if "imported-from" in c.metadata.get("tags", [])]
    paths = "".join(o.get("text", "") for o in _outputs(cell)).split()
    assert [Path(p).parent.parent for p in paths] == [ROOT, ROOT]


def test_the_served_page_builds_without_a_server():
    """app.main's page and the explorer are built outside a server (a notebook, a script):
    no page address is assumed."""
    import panel as pn

    from app.main import create_app

    template = create_app()
    assert template.explorer.location is None
    assert pn.panel(template.explorer).get_root() is not None


def test_every_cell_runs_without_an_error(executed):
    code = [cell for cell in executed.cells if cell.cell_type == "code"]
    assert code and all(cell.get("execution_count") for cell in code)
    for cell in code:
        errors = [o for o in _outputs(cell) if o["output_type"] == "error"]
        assert not errors, (cell.source, errors)
        streams = "".join(o.get("text", "") for o in _outputs(cell)
                          if o["output_type"] == "stream" and o.get("name") == "stderr")
        assert "Traceback" not in streams, (cell.source, streams)


def test_the_explorer_and_a_component_display(executed):
    """The explorer's cell, the controls' cell and the lesson's cell each display a Panel
    object (its notebook MIME bundle), not just a repr."""
    shown = [cell for cell in executed.cells if cell.cell_type == "code"
             and ("explorer\n" in cell.source + "\n" or "sidebar()" in cell.source
                  or "player.layout" in cell.source)]
    assert len(shown) == 3
    for cell in shown:
        data = [o.get("data", {}) for o in _outputs(cell) if o["output_type"] ==
                "display_data" or o["output_type"] == "execute_result"]
        assert any("application/vnd.holoviews_exec.v0+json" in d for d in data), cell.source


def _numbers(executed) -> dict:
    [cell] = [c for c in executed.cells if "figure-numbers" in c.metadata.get("tags", [])]
    text = "".join(o.get("text", "") for o in _outputs(cell) if o["output_type"] == "stream")
    return json.loads(text)


def test_fig_4a_matches_the_closed_form(executed):
    """Elastic impact, fast belt, a < x_bar < 2a: impacts at speed sqrt(x_bar (2a - x_bar)),
    period 2 arccos(1 - x_bar / a)."""
    fig = _numbers(executed)["4a"]
    x_bar = 0.3
    assert fig["kind"] == "periodic"
    assert fig["impact_speed"] == pytest.approx(math.sqrt(x_bar * (2 * A - x_bar)), rel=REL)
    assert fig["period"] == pytest.approx(2 * math.acos(1 - x_bar / A), rel=REL)


def test_fig_7b_matches_the_closed_form(executed):
    """Inelastic impact, slow belt, case b: the stick carries the mass into the stop at v,
    it rebounds at -r v on the circle about (a, 0) of radius R = sqrt((x_bar - a)^2 +
    (r v)^2) and meets the stick line x' = v at x_s = a - sqrt(R^2 - v^2); the period is
    the arc from the rebound to x_s plus the stick (x_bar - x_s) / v."""
    fig = _numbers(executed)["7b"]
    v, x_bar, r = 0.07, 0.285, 0.3
    radius = math.hypot(x_bar - A, r * v)
    x_s = A - math.sqrt(radius**2 - v**2)
    arc = math.pi + math.asin(v / radius) - math.atan2(r * v, x_bar - A)
    assert fig["kind"] == "periodic"
    assert fig["impact_speed"] == pytest.approx(v, rel=REL)
    assert fig["rebound_speed"] == pytest.approx(-r * v, rel=REL)
    assert fig["stick_start"] == pytest.approx(x_s, rel=REL)
    assert fig["period"] == pytest.approx(arc + (x_bar - x_s) / v, rel=REL)
