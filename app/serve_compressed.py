"""``panel serve`` whose HTTP answers are gzip-compressed:
``python -m app.serve_compressed [panel serve arguments]`` (what ``scripts/serve.sh`` runs).

A first open of the page is ~3.5 MB of JavaScript and CSS; on a classroom's shared Wi-Fi,
30 students opening it at once wait for the air, not the server. ``panel serve`` has no
option for HTTP compression (``--websocket-compression-level`` is the websocket's); its
server is a Tornado application, whose ``compress_response`` setting gzips text answers
(JavaScript, CSS, HTML, JSON) for browsers that accept it. Bokeh's ``serve`` command offers
``customize_kwargs`` for subclasses to add such server settings; Panel's ``serve`` is such a
subclass, and this is one more.

Behind nginx (``docs/nginx-example.conf``), nginx compresses, in a process of its own:
there ``scripts/serve.sh`` runs ``panel serve`` itself, so that the server's event loop does
not spend ~0.1 s of CPU compressing each new browser's bundles.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from panel.command.serve import Serve


class CompressedServe(Serve):
    """Panel's ``serve`` command with Tornado's ``compress_response`` on."""

    def customize_kwargs(self, args: argparse.Namespace,
                         server_kwargs: dict[str, Any]) -> dict[str, Any]:
        kwargs = super().customize_kwargs(args, server_kwargs)
        kwargs["compress_response"] = True  # passed on to tornado.web.Application
        return kwargs


def main(argv: list[str] | None = None) -> int:
    """Parse ``argv`` as ``panel serve`` does and serve until stopped."""
    parser = argparse.ArgumentParser(prog="panel serve (compressed)")
    command = CompressedServe(parser=parser)
    ret = command.invoke(parser.parse_args(sys.argv[1:] if argv is None else argv))
    return 1 if ret is False else 0


if __name__ == "__main__":
    sys.exit(main())
