"""The server's word to the page's scripts: which of their patches apply.

A script in ``static/`` that overrides a BokehJS internal, or a browser method that Panel or
BokehJS calls, holds patches of :data:`app.perf.PATCHES` (those whose ``where`` names the
script). The server decides, as for its own patches, whether each applies (the switch
``EXPLORER_PERF_PATCHES`` and the version window, :func:`app.perf.applies`) and writes the
names of those that do into the script's address: ``assets/a11y.js?apply=slider-handle-names``,
or ``?apply=`` for none. The script reads its own address (``document.currentScript``) and
applies only the patches named there; a script loaded without the parameter applies none.
"""

from __future__ import annotations

from collections.abc import Mapping

from app.perf import PATCHES, applies

#: Query parameter of a script's address that lists the patches to apply.
PARAMETER = "apply"


def script_patches(path: str) -> list[str]:
    """Names of the page patches held by the script at ``path`` (``static/...``)."""
    return [p.name for p in PATCHES.values() if p.in_page and path in p.where]


def page_scripts(files: Mapping[str, str], assets: str = "assets",
                 static: str = "static") -> dict[str, str]:
    """``files`` (name -> address under ``assets/``) with each patching script's address
    naming the patches that apply; other scripts are left as they are."""
    out = {}
    for name, url in files.items():
        path = static + url[len(assets):] if url.startswith(assets + "/") else url
        held = script_patches(path)
        if held:
            url = f"{url}?{PARAMETER}=" + ",".join(n for n in held if applies(n))
        out[name] = url
    return out
