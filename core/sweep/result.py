"""The value a sweep returns: steady-state quantities per parameter point, numpy arrays.

The Poincaré samples of each point are the transitions of one steady period (paper Eq. 20:
the fixed point of the friction-impact map and its images). They are ragged, so they are
kept as flat arrays with ``offsets``: the transitions of point ``i`` are
``cycle_*[offsets[i]:offsets[i + 1]]``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from core.result import SteadyKind, TransitionKind

#: Steady-state labels, in the order of their integer codes in :attr:`SweepResult.label`.
LABELS = tuple(kind.value for kind in SteadyKind)
#: Transition kinds, in the order of their integer codes in :attr:`SweepResult.cycle_kind`.
KINDS = tuple(TransitionKind)
KIND_CODE = {kind: i for i, kind in enumerate(KINDS)}
LABEL_CODE = {kind: i for i, kind in enumerate(SteadyKind)}

_IMPACTS = (KIND_CODE[TransitionKind.IMPACT], KIND_CODE[TransitionKind.STICK_IMPACT])

#: Poincaré quantities: which transitions of a period they sample and what they read there.
QUANTITIES = {
    "stick_x": "x at each slip->stick (the stick->slip point is always x = b, Eq. 6)",
    "impact_speed": "approach speed at each impact (rigid) or contact (deformable stop)",
    "rebound_speed": "speed after each impact (rigid) or at each separation (deformable)",
    "transition_x": "x at every transition of the period",
    "force_peak": "peak contact force over k of each contact (deformable stop)",
}


def check_quantity(quantity: str, deformable: bool) -> str:
    """A known Poincaré quantity, or a ``ValueError`` listing them."""
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {', '.join(QUANTITIES)}; got {quantity!r}")
    if quantity == "force_peak" and not deformable:
        raise ValueError(
            "quantity 'force_peak' needs a HystereticStop (a rigid stop acts by impulses)"
        )
    return quantity


def select(
    quantity: str,
    kind: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    v_after: np.ndarray,
    force: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Which cycle transitions a quantity samples (a mask) and the values it reads."""
    if quantity == "stick_x":
        return kind == KIND_CODE[TransitionKind.SLIP_STICK], x
    if quantity == "transition_x":
        return np.ones(len(kind), bool), x
    contact = kind == KIND_CODE[TransitionKind.CONTACT]
    separation = kind == KIND_CODE[TransitionKind.SEPARATION]
    impact = np.isin(kind, _IMPACTS)
    if quantity == "impact_speed":
        return impact | contact, v
    if quantity == "rebound_speed":
        return impact | separation, np.where(separation, -v, -v_after)
    return separation, force


def _frozen(a) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class SteadyArrays:
    """Per-point steady state and the flat Poincaré cycles: the fields a sweep's blocks
    (:class:`LaneRecords`) and its result (:class:`SweepResult`) share; see
    :class:`SweepResult` for their meaning."""

    label: np.ndarray
    period: np.ndarray
    transitions_per_period: np.ndarray
    x_max: np.ndarray
    impact_speed: np.ndarray
    cycle_kind: np.ndarray
    cycle_x: np.ndarray
    cycle_v: np.ndarray
    cycle_v_after: np.ndarray
    cycle_force: np.ndarray
    offsets: np.ndarray
    fallback: np.ndarray

    def steady_arrays(self) -> dict[str, np.ndarray]:
        """The shared fields by name."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(SteadyArrays)}


#: Fields of :class:`SteadyArrays` with one entry per point, and with one per transition of
#: the cycles (indexed through ``offsets``).
POINT_FIELDS = ("label", "period", "transitions_per_period", "x_max", "impact_speed", "fallback")
CYCLE_FIELDS = ("cycle_kind", "cycle_x", "cycle_v", "cycle_v_after", "cycle_force")


@dataclass(frozen=True)
class SweepResult(SteadyArrays):
    """Steady state at every parameter point of a sweep (arrays are read-only).

    Attributes
    ----------
    parameters : tuple of str
        The swept parameters; ``axes[name]`` holds each one's values.
    shape : tuple of int
        ``(n,)`` for one parameter, ``(n1, n2)`` for a grid; per-point arrays are flat in
        row-major order (reshape with ``shape``).
    label : ndarray of int8
        Steady-state kind, an index into :data:`LABELS`.
    period, x_max, impact_speed : ndarray of float
        As :class:`core.result.Steady` (``nan`` where undefined).
    transitions_per_period : ndarray of int64
    regime : ndarray of int32
        Simulated regime label, an index into ``regimes``: the steady kind and, for a
        periodic motion, its transition sequence (e.g. ``'periodic: slip->stick ->
        stick->slip'``).
    cycle_kind, cycle_x, cycle_v, cycle_v_after, cycle_force : ndarray
        Transitions of one steady period per point (flat; see ``offsets``): kind (index
        into :data:`KINDS`), position, velocity before and after, peak contact force over
        ``k`` of the contact a separation ends (``nan`` elsewhere). A grazing motion holds
        its limit, one impact of speed 0 at the stop.
    offsets : ndarray of int64
        ``len(label) + 1`` bounds into the ``cycle_*`` arrays.
    fallback : ndarray of bool
        True where the point was solved by :func:`core.simulate` one by one instead of the
        vectorised closed form (always for a deformable stop or a numerical method).
    quantity : str
        The default Poincaré quantity of :meth:`samples`.
    """

    parameters: tuple[str, ...]
    axes: dict[str, np.ndarray]
    shape: tuple[int, ...]
    regime: np.ndarray
    regimes: tuple[str, ...]
    quantity: str
    t_end: float
    method: str

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, f.name, _frozen(value))
        object.__setattr__(self, "axes", {k: _frozen(v) for k, v in self.axes.items()})

    def __len__(self) -> int:
        return len(self.label)

    @property
    def labels(self) -> np.ndarray:
        """Steady-state labels as strings, shaped like the sweep."""
        return np.asarray(LABELS, dtype=object)[self.label].reshape(self.shape)

    @property
    def regime_labels(self) -> np.ndarray:
        """Simulated regime labels as strings, shaped like the sweep."""
        return np.asarray(self.regimes, dtype=object)[self.regime].reshape(self.shape)

    def samples(self, quantity: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Poincaré samples of one quantity: ``(values, offsets)``, flat and ragged.

        The samples of point ``i`` are ``values[offsets[i]:offsets[i + 1]]``.
        """
        quantity = check_quantity(quantity or self.quantity, deformable=True)
        mask, values = select(
            quantity, self.cycle_kind, self.cycle_x, self.cycle_v, self.cycle_v_after,
            self.cycle_force,
        )
        lane = np.repeat(np.arange(len(self)), np.diff(self.offsets))
        counts = np.bincount(lane[mask], minlength=len(self))
        offsets = np.concatenate(([0], np.cumsum(counts))).astype(np.int64)
        return values[mask], offsets

    def points(self, quantity: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Bifurcation-diagram points of a one-parameter sweep: ``(parameter, sample)``."""
        if len(self.parameters) != 1:
            raise ValueError("points() needs a one-parameter sweep; use samples() on a grid")
        values, offsets = self.samples(quantity)
        return np.repeat(self.axes[self.parameters[0]], np.diff(offsets)), values

    def to_npz(self, path) -> None:
        """Write every field to a ``.npz`` file (strings as arrays of str)."""
        data = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        axes = data.pop("axes")
        out = {k: np.asarray(v) for k, v in data.items()}
        out["parameters"] = np.asarray(self.parameters, dtype=str)
        out["regimes"] = np.asarray(self.regimes, dtype=str)
        for name, values in axes.items():
            out[f"axis_{name}"] = values
        np.savez_compressed(path, **out)

    @classmethod
    def from_npz(cls, path) -> SweepResult:
        """Read a file written by :meth:`to_npz`."""
        with np.load(path, allow_pickle=False) as f:
            parameters = tuple(str(p) for p in f["parameters"])
            kwargs = {
                fl.name: f[fl.name]
                for fl in dataclasses.fields(cls)
                if fl.name not in ("parameters", "axes")
            }
            kwargs["axes"] = {p: f[f"axis_{p}"] for p in parameters}
        kwargs["shape"] = tuple(int(s) for s in kwargs["shape"])
        kwargs["regimes"] = tuple(str(s) for s in kwargs["regimes"])
        kwargs["quantity"] = str(kwargs["quantity"])
        kwargs["method"] = str(kwargs["method"])
        kwargs["t_end"] = float(kwargs["t_end"])
        return cls(parameters=parameters, **kwargs)


@dataclass(frozen=True)
class LaneRecords(SteadyArrays):
    """Per-lane outputs of one block of lanes, before they become a :class:`SweepResult`.

    The solvers fill the per-point arrays in place and set the cycles with
    :func:`dataclasses.replace`. ``sequence`` holds, per lane, the transition-kind codes of
    the steady period's sequence as a tuple (the regime label's second half).
    """

    sequence: list[tuple[int, ...]]

    @classmethod
    def empty(cls, n: int) -> LaneRecords:
        nan = np.full(n, np.nan)
        return cls(
            label=np.full(n, LABEL_CODE[SteadyKind.NONE], np.int8),
            period=nan.copy(),
            transitions_per_period=np.zeros(n, np.int64),
            x_max=nan.copy(),
            impact_speed=nan.copy(),
            sequence=[()] * n,
            cycle_kind=np.zeros(0, np.int8),
            cycle_x=np.zeros(0),
            cycle_v=np.zeros(0),
            cycle_v_after=np.zeros(0),
            cycle_force=np.zeros(0),
            offsets=np.zeros(n + 1, np.int64),
            fallback=np.zeros(n, bool),
        )

    @staticmethod
    def concat(parts: list[LaneRecords]) -> LaneRecords:
        """Join blocks of lanes in order."""
        starts = np.cumsum([0] + [p.offsets[-1] for p in parts[:-1]])
        offsets = np.concatenate(
            [[0]] + [p.offsets[1:] + s for p, s in zip(parts, starts, strict=True)]
        )
        cat = {
            name: np.concatenate([getattr(p, name) for p in parts])
            for name in POINT_FIELDS + CYCLE_FIELDS
        }
        sequence = [s for p in parts for s in p.sequence]
        return LaneRecords(sequence=sequence, offsets=offsets.astype(np.int64), **cat)

    def take(self, i: int, j: int) -> LaneRecords:
        """The lanes ``i`` to ``j - 1``."""
        lo, hi = self.offsets[i], self.offsets[j]
        return LaneRecords(
            sequence=self.sequence[i:j],
            offsets=self.offsets[i : j + 1] - lo,
            **{name: getattr(self, name)[i:j] for name in POINT_FIELDS},
            **{name: getattr(self, name)[lo:hi] for name in CYCLE_FIELDS},
        )

    def finish(
        self,
        parameters: tuple[str, ...],
        axes: dict[str, np.ndarray],
        quantity: str,
        t_end: float,
        method: str,
    ) -> SweepResult:
        """The :class:`SweepResult` of these lanes, with the regime table built."""
        names: list[str] = []
        index: dict[tuple[int, tuple[int, ...]], int] = {}

        def code(label: int, seq: tuple[int, ...]) -> int:
            found = index.get((label, seq))
            if found is None:
                text = LABELS[label]
                if seq:
                    text += ": " + " -> ".join(KINDS[k].value for k in seq)
                found = index[(label, seq)] = len(names)
                names.append(text)
            return found

        # Points without a sequence are labelled by their steady kind alone (vectorised);
        # only those with one are looked up one by one.
        by_label = np.array([code(i, ()) if np.any(self.label == i) else -1
                             for i in range(len(LABELS))], np.int32)
        regime = by_label[self.label]
        for i, seq in enumerate(self.sequence):
            if seq:
                regime[i] = code(int(self.label[i]), seq)
        used = np.unique(regime)
        if len(used) < len(names):  # drop labels that only sequences' points had
            remap = np.full(len(names), -1, np.int32)
            remap[used] = np.arange(len(used), dtype=np.int32)
            regime = remap[regime]
            names = [names[k] for k in used.tolist()]
        shape = tuple(len(axes[p]) for p in parameters)
        return SweepResult(
            parameters=parameters,
            axes=axes,
            shape=shape,
            regime=regime,
            regimes=tuple(names),
            quantity=quantity,
            t_end=t_end,
            method=method,
            **self.steady_arrays(),
        )
