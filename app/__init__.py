"""The Friction-Impact Explorer: a Panel dashboard on top of :mod:`core`.

``app.main`` is the entry point served by ``panel serve app/main.py``. The modules here hold
the UI state (:mod:`app.state`), the paper's scenes (:mod:`app.scenes`), the page's solves
(:mod:`app.solve`), the Bokeh figures (:mod:`app.plots`), the readout
(:mod:`app.readout`), the client-side animation (:mod:`app.animation`) and the CSV export
(:mod:`app.export`). Nothing here runs at import time beyond defining them.
"""
