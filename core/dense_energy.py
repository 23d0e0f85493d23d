"""The energy terms of a numerical method's solution at its samples (docs/physics.md).

Friction work, belt work and the work done on the stop, summed along the integrator's points
by rules exact on each kind of interval and carried to the samples inside them; the energy
balance of every numerical method's result is built from them (:mod:`core.dense`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from core.result import Mode


class StopWorkSamples(NamedTuple):
    """A deformable stop's work in closed form (:class:`core.deformable.stop_work.StopWork`): at the
    points, at the samples, and where the mass sticks in contact (mode ``CONTACT``, where
    the friction force is ``x + phi`` as on free stick)."""

    points: np.ndarray
    samples: np.ndarray
    stuck: np.ndarray


def energy_at_samples(
    t: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    mode: np.ndarray,
    acc: np.ndarray | None,
    phi: np.ndarray,
    belt_speed: float,
    idx: np.ndarray,
    ts: np.ndarray,
    xs: np.ndarray,
    phis: np.ndarray,
    stop_work: StopWorkSamples | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Friction work, belt work and work done on the stop at the samples (per unit ``k``).

    Friction force over ``k`` on the interval after point ``i``: ``f = x'' + x + phi`` (the
    equation of motion solved for it, ``docs/physics.md``). On slip it is the constant ``s*a``
    (``+-b`` in the switch model's transition band), so its work ``f * dx`` is exact; on
    stick it is the spring-plus-contact force, summed by the trapezoid rule in ``x`` (exact
    off the stop, where it is linear in ``x``). A jump (rigid impact) hands its loss of
    kinetic energy to the stop; the deformable stop's work is the trapezoid rule in ``x``,
    or ``stop_work``, its values at the points and at the samples in closed form along the
    law's branches (then the contact force's work on stick is exact too).
    Inside an interval the same rules run from its start point to the sample, so the sums
    at the samples are as accurate as at the points.
    """
    n = len(t)
    if n < 2:
        z = np.zeros(len(ts))
        return z, z.copy(), z.copy()
    mech = 0.5 * (x * x + v * v)
    dx, dt = np.diff(x), np.diff(t)
    jump = dt == 0.0
    stick = mode[:-1] == Mode.STICK
    if stop_work is not None:
        stick = stick | stop_work.stuck[:-1]
    k = np.clip(idx, 0, n - 2)
    d_x = xs - x[k]
    phi_mid = 0.5 * (phi[:-1] + phi[1:])
    if stop_work is None:
        cum_stop = np.concatenate([[0.0], np.cumsum(np.where(jump, -np.diff(mech),
                                                             phi_mid * dx))])
        stop_s = cum_stop[k] + np.where(jump[k], 0.0, 0.5 * (phi[k] + phis) * d_x)
    else:
        w_points, stop_s = stop_work.points, stop_work.samples
    if acc is None:
        # no acceleration given: the caller closes the balance with the friction work
        return np.full(len(ts), math.nan), np.full(len(ts), math.nan), stop_s
    f_left = acc[:-1] + x[:-1] + phi[:-1]
    # On stick the friction force is the spring's and the stop's, x + phi: its mean over
    # an interval by the trapezoid rule, or from the stop's work in closed form.
    if stop_work is None:
        f_stick = 0.5 * (x[:-1] + x[1:]) + phi_mid
        f_stick_s = 0.5 * (x[k] + phi[k] + xs + phis)
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            f_stick = np.where(dx != 0.0, 0.5 * (x[:-1] + x[1:]) + np.diff(w_points) / dx,
                               f_left)
            f_stick_s = np.where(d_x != 0.0, 0.5 * (x[k] + xs) + (stop_s - w_points[k]) / d_x,
                                 f_left[k])
    f_int = np.where(stick, f_stick, f_left)
    fric = np.where(jump, 0.0, f_int * dx)
    belt = np.where(jump, 0.0, f_int * belt_speed * dt)
    cum_f = np.concatenate([[0.0], np.cumsum(fric)])
    cum_b = np.concatenate([[0.0], np.cumsum(belt)])
    f_s = np.where(stick[k], f_stick_s, f_left[k])
    f_s = np.where(jump[k], 0.0, f_s)
    fric_s = cum_f[k] + f_s * d_x
    belt_s = cum_b[k] + f_s * belt_speed * (ts - t[k])
    return fric_s, belt_s, stop_s
