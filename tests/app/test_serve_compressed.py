"""app.serve_compressed: `panel serve` with Tornado's gzip of HTTP answers."""

from __future__ import annotations

import argparse

from app.serve_compressed import CompressedServe


def _kwargs(command_class) -> dict:
    parser = argparse.ArgumentParser()
    command = command_class(parser=parser)
    args = parser.parse_args(["app/main.py", "--port", "0"])
    return command.customize_kwargs(args, {"port": 0})


def test_the_server_settings_ask_tornado_to_compress_and_keep_panel_s_own():
    from panel.command.serve import Serve

    panel_kwargs = _kwargs(Serve)
    ours = _kwargs(CompressedServe)
    assert "compress_response" not in panel_kwargs  # panel serve alone does not compress
    assert ours.pop("compress_response") is True
    assert ours.keys() == panel_kwargs.keys()  # everything else as panel serve sets it
