"""The page's solves: what a run is given, where it runs, what is kept, what is measured.

:mod:`~app.solve.presets` (accuracy presets, budgets, the method each choice runs),
:mod:`~app.solve.solution` (one solve of the page's state: a :class:`Solution`),
:mod:`~app.solve.measure` (a run's error against the exact method),
:mod:`~app.solve.theory` (the paper's closed forms for the state),
:mod:`~app.solve.regime_map` (the regime map and its axes),
:mod:`~app.solve.cache` (the bounded stores of solutions, references and maps),
:mod:`~app.solve.pool` (the server's worker threads, shared solves and their cache),
:mod:`~app.solve.runner` (one session's solves: the latest wins, answers on its loop),
:mod:`~app.solve.process` (child processes that hold no lock of the server),
:mod:`~app.solve.trade` and :mod:`~app.solve.trade_solve` ("Measure the trade").

Nothing is imported here: a solver process imports :mod:`~app.solve.process` and
:mod:`~app.solve.trade_solve` without Panel.
"""
