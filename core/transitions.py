"""The transition log: every transition a method finds, the first ones stored, all counted.

One log for every method (docs/physics.md, "Transitions"): the exact solver records the
events of its closed form, the hysteretic solver its contacts, the numerical methods
what their event location finds. Memory stays bounded on long horizons: the first
``cap`` transitions are stored for the result (and, past them, the few that say how the
run was solved or ended: :data:`LANDMARKS`), the last ``window`` are kept for the
steady-state search (:mod:`core.steady`), and every transition is counted by kind.

A method builds one ``TransitionLog(cap, window)``, calls :meth:`TransitionLog.add`
per transition (and :meth:`~TransitionLog.count` for transitions known only by
number, e.g. the impacts of a grazing sequence beyond the horizon's samples), and hands
:meth:`TransitionLog.result_fields` to its :class:`~core.result.Result`.
"""

from __future__ import annotations

from collections import Counter, deque
from collections.abc import Iterable, Sequence

from core.result import Transition, TransitionKind

#: Transitions at which the stop takes an impulse ``m (v - v_after)``.
IMPACT_KINDS = (TransitionKind.IMPACT, TransitionKind.STICK_IMPACT)
#: Kinds stored even past the cap: a switch into a reduced model, rest and a failed stop
#: happen once or twice in a run, and the readout and the plots show them (a reduced
#: model's start and stated error, where the mass came to rest) whatever the run's length:
#: a soft stop's 13,000 reversals by t = 1e4 must not hide the model that ended them.
LANDMARKS = frozenset({TransitionKind.REDUCED, TransitionKind.REST, TransitionKind.FAILURE})
#: Each kind's value, looked up without the enum's property (a long horizon records
#: hundreds of thousands of transitions).
_VALUE = {kind: kind.value for kind in TransitionKind}


class TransitionLog:
    """Transitions: the first ``cap`` stored (and the :data:`LANDMARKS` after them), the
    last ``window`` kept, all counted.

    Attributes
    ----------
    stored : list of Transition
        The first ``cap`` transitions, then only :data:`LANDMARKS`, in time order.
    recent : deque of Transition
        The last ``window`` transitions (empty when ``window = 0``).
    counts : Counter
        Transitions per kind value, stored or not.
    total : int
        All transitions.
    impulses : list of (float, float)
        Time and impulse per unit ``m omega`` (``v - v_after``) of each stored impact.

    Examples
    --------
    >>> log = TransitionLog(cap=1)
    >>> log.add(TransitionKind.SLIP_STICK, 1.0, 0.02, 0.1)
    >>> log.add(TransitionKind.STICK_SLIP, 2.0, 0.3, 0.1)
    >>> len(log.stored), log.total, log.counts["stick->slip"]
    (1, 2, 1)
    """

    __slots__ = ("cap", "stored", "recent", "counts", "total", "impulses")

    def __init__(self, cap: int, window: int = 0) -> None:
        self.cap = int(cap)
        self.stored: list[Transition] = []
        self.recent: deque[Transition] = deque(maxlen=int(window))
        self.counts: Counter[str] = Counter()
        self.total = 0
        self.impulses: list[tuple[float, float]] = []

    @property
    def full(self) -> bool:
        """True once ``cap`` transitions are stored."""
        return len(self.stored) >= self.cap

    def add(
        self,
        kind: TransitionKind,
        t: float,
        x: float,
        v: float,
        v_after: float | None = None,
    ) -> None:
        """Record one transition with the state ``(x, v)`` before it (``v_after`` after
        it; the same as ``v`` unless it is an impact)."""
        after = v if v_after is None else v_after
        tr = Transition(kind, float(t), float(x), float(v), float(after))
        self.total += 1
        self.counts[_VALUE[kind]] += 1
        if len(self.stored) < self.cap or kind in LANDMARKS:
            self.stored.append(tr)
            if kind is TransitionKind.IMPACT or kind is TransitionKind.STICK_IMPACT:
                self.impulses.append((tr.t, tr.v - tr.v_after))
        if self.recent.maxlen:
            self.recent.append(tr)

    def count(self, kind: TransitionKind, n: int) -> None:
        """Count ``n`` transitions of ``kind`` that are not stored."""
        self.total += int(n)
        self.counts[_VALUE[kind]] += int(n)

    def add_impacts(
        self, times: Sequence[float], x: float, speeds: Sequence[float], r: float
    ) -> None:
        """Record impacts at ``x`` with approach ``speeds`` and rebound ``-r * speed``
        (Eq. 8) in bulk: as many as there is room for are stored, all are counted (not
        kept in ``recent``: a closed-form sequence needs no steady-state search)."""
        room = max(0, min(len(times), self.cap - len(self.stored)))
        kind = TransitionKind.IMPACT
        pairs = list(zip(list(times[:room]), list(speeds[:room]), strict=True))
        self.stored.extend(Transition(kind, float(t), x, float(w), -r * float(w)) for t, w in pairs)
        self.impulses.extend((float(t), (1.0 + r) * float(w)) for t, w in pairs)
        self.count(kind, len(times))

    def extend(self, transitions: Iterable[Transition]) -> None:
        """Record transitions in time order."""
        for tr in transitions:
            self.add(tr.kind, tr.t, tr.x, tr.v, tr.v_after)

    def tile(self, cycle: Sequence[Transition], period: float, t_end: float) -> None:
        """Repeat the transitions of one period (``cycle``, already recorded) shifted by
        whole periods up to ``t_end``; once the store is full the rest is counted."""
        if not cycle or not period > 0.0:
            return
        t_first = cycle[0].t
        k = 1
        while t_first + k * period <= t_end:
            if self.full:
                remaining = t_end - (t_first + k * period)
                whole = int(remaining // period)
                for tr in cycle:
                    self.count(tr.kind, whole)
                last_start = t_first + (k + whole) * period
                for tr in cycle:
                    if tr.t - t_first + last_start <= t_end:
                        self.count(tr.kind, 1)
                return
            shift = k * period
            for tr in cycle:
                if tr.t + shift > t_end:
                    return
                self.add(tr.kind, tr.t + shift, tr.x, tr.v, tr.v_after)
            k += 1

    def result_fields(self) -> dict[str, object]:
        """The :class:`~core.result.Result` fields this log fills."""
        return {
            "transitions": tuple(self.stored),
            "transition_counts": dict(self.counts),
            "n_transitions": self.total,
        }

    @classmethod
    def from_sequence(cls, transitions: Sequence[Transition], cap: int) -> TransitionLog:
        """A log holding ``transitions`` (in time order)."""
        log = cls(cap)
        log.extend(transitions)
        return log
