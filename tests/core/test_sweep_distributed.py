"""core.sweep on Dask: a 2-worker LocalCluster gives the serial result exactly; the CLI."""

from __future__ import annotations

import dataclasses

import dask.distributed as distributed
import numpy as np
import pytest

from core import HystereticStop, Oscillator, RigidStop
from core.sweep import plan_grid, sweep_grid
from core.sweep.__main__ import main
from core.sweep.distributed import run_chunks, sweep_distributed
from core.sweep.result import SweepResult


def _assert_identical(a: SweepResult, b: SweepResult) -> None:
    for field in dataclasses.fields(SweepResult):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if isinstance(x, np.ndarray):
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), field.name
        elif field.name == "axes":
            assert x.keys() == y.keys()
            assert all(np.array_equal(x[k], y[k]) for k in x)
        else:
            assert x == y, field.name


@pytest.fixture(scope="module")
def client():
    # Threads in this process keep the cluster's start-up to a fraction of a second; the
    # chunks are the same tasks a process-based or remote cluster runs.
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_deformable_stop_sweep_on_two_workers_equals_the_serial_one(client):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.07)
    stop = HystereticStop(
        clearance=0.24, k_c0=400.0, k_e0=36.0, limit_overlap=0.02, beta_c=40.0, beta_e=40.0
    )
    axes = {"belt_speed": np.linspace(0.03, 0.2, 6)}
    # A tiny task time so that the six points become several chunks on both workers.
    dist = sweep_distributed(
        osc, stop, axes, t_end=40.0, quantity="force_peak", client=client,
        task_seconds=1e-3, progress=None,
    )
    serial = sweep_grid(osc, stop, axes, t_end=40.0, quantity="force_peak")
    _assert_identical(dist, serial)
    assert dist.fallback.all()


def test_rigid_grid_on_two_workers_equals_the_serial_one(client):
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    stop = RigidStop(0.25, 0.7)
    axes = {"belt_speed": np.linspace(0.01, 0.4, 60), "clearance": np.linspace(0.05, 0.5, 50)}
    plan = plan_grid(osc, stop, axes, t_end=200.0)
    rec, info = run_chunks(plan, client=client, task_seconds=1e-3, progress=None)
    assert info["chunks"] > 2  # the grid really was split over the workers
    dist = plan.finish(rec)
    _assert_identical(dist, sweep_grid(osc, stop, axes))


def test_cli_writes_the_sweep_it_would_return(tmp_path, capsys):
    out = tmp_path / "sweep.npz"
    assert main(
        ["--param", "belt_speed", "0.01:0.4:50", "--clearance", "0.25", "--restitution",
         "0.7", "--out", str(out)]
    ) == 0
    osc = Oscillator(mu_s=0.3, mu_k=0.2, belt_speed=0.1)
    expected = sweep_grid(
        osc, RigidStop(0.25, 0.7), {"belt_speed": np.linspace(0.01, 0.4, 50)}
    )
    _assert_identical(SweepResult.from_npz(out), expected)
    err = capsys.readouterr().err
    assert "50 points" in err and "chunks" in err


def test_cli_refuses_a_bad_range_and_an_unknown_parameter(tmp_path):
    with pytest.raises(SystemExit, match="START:STOP:NUM"):
        main(["--param", "belt_speed", "0.1:1", "--out", str(tmp_path / "a.npz")])
    with pytest.raises(SystemExit, match="parameter must be one of"):
        main(["--param", "speed", "0.1:1:3", "--out", str(tmp_path / "a.npz")])
    with pytest.raises(SystemExit, match="must end in .npz or .parquet"):
        main(["--param", "belt_speed", "0.1:1:3", "--out", str(tmp_path / "a.csv")])
