"""``companion tablet`` (the robot's tablet alone, over the dialogue of ``companion chat``)
and ``companion view RUN_DIR`` (the live view over a finished run, with a time slider).
``companion run --tablet`` is an option of ``companion run`` (app/run_cli.py).

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from core.cli_args import integer
from core.errors import UserError
from core.signals import Terminated


def add_server_options(p: argparse.ArgumentParser) -> None:
    """``--host`` and ``--port``, shared by every command that serves the tablet."""
    p.add_argument("--host", help="address to serve on (default: 127.0.0.1, this machine "
                   "only; any other needs the token printed at start)")
    p.add_argument("--port", type=integer(0, 65535),
                   help="port (default: config/tablet.yaml's; 0 picks a free one)")
    p.add_argument("--tablet-config", type=Path, help="YAML over config/tablet.yaml")


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``tablet`` and ``view``."""
    p = sub.add_parser("tablet", help="serve the robot's tablet page (dialogue only)",
                       description="Serve the robot's chest tablet in a browser: a button "
                       "per kind of conversation, a text box, each reply with its card drawn "
                       "from local data, and feedback buttons. /mind shows the mood and the "
                       "dialogue. Stop with Ctrl-C.")
    p.add_argument("--scenario", type=Path, default=None,
                   help="scenario YAML for the household map, the weather and the robot's "
                        "drives (default: worlds/living_room.yaml for the map, drives all 0)")
    p.add_argument("--out", type=Path, default=None,
                   help="keep the session's maps, photos and reply log here (default: a "
                        "temporary folder, removed at the end)")
    add_server_options(p)
    p.set_defaults(func=tablet_command)
    v = sub.add_parser("view", help="replay a finished run's mind with a time slider",
                       description="Serve the live view of the robot's mind over a finished "
                       "run folder (timeline.csv, events.jsonl, dialogue.jsonl, view/ frames) "
                       "with a time slider. Stop with Ctrl-C.")
    v.add_argument("run_dir", type=Path, help="a `companion run` folder")
    add_server_options(v)
    v.set_defaults(func=view_command)


def serve_until_stopped(backend: Any, args: argparse.Namespace, what: str) -> int:
    """Serve ``backend`` until Ctrl-C or SIGTERM, having printed where."""
    from app.tablet.serve import TabletServer

    cfg = backend.config.server
    server = TabletServer(backend, args.host or cfg.host,
                          cfg.port if args.port is None else args.port)
    with server:
        try:   # from here on Ctrl-C is how a person closes the server
            print(f"{what}: {server.url}", flush=True)
            if server.token:
                print(f"token: {server.token} (give it once as ?token=...)", flush=True)
            while True:
                time.sleep(0.5)
        except Terminated:   # SIGTERM: exit 143, as every command does
            raise
        except KeyboardInterrupt:
            print("stopped", flush=True)
    return 0


def tablet_command(args: argparse.Namespace) -> int:
    """Handler of ``companion tablet``."""
    from app.tablet.chat_link import ChatTablet
    from app.tablet.config import load_tablet_config

    config = load_tablet_config(args.tablet_config)
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        return serve_until_stopped(ChatTablet.from_scenario(args.scenario, config, args.out),
                                   args, "tablet")
    with tempfile.TemporaryDirectory(prefix="companion-tablet-") as tmp:
        backend = ChatTablet.from_scenario(args.scenario, config, Path(tmp))
        try:
            return serve_until_stopped(backend, args, "tablet")
        finally:
            backend.close()


def view_command(args: argparse.Namespace) -> int:
    """Handler of ``companion view``."""
    from app.tablet.config import load_tablet_config
    from app.tablet.replay import ReplayView

    backend = ReplayView(args.run_dir, load_tablet_config(args.tablet_config))
    return serve_until_stopped(backend, args, f"replay of {args.run_dir} (open /mind)")


@contextmanager
def tablet_serving(args: argparse.Namespace) -> Iterator[Any]:
    """With ``--tablet``: a :class:`~app.tablet.run_link.RunTablet` served for the length of
    the block (its address printed first); without it, None (``--host``/``--port`` refused)."""
    if not args.tablet:
        if args.host is not None or args.port is not None or args.tablet_config is not None:
            raise UserError("--host, --port and --tablet-config need --tablet")
        yield None
        return
    from app.tablet.config import load_tablet_config
    from app.tablet.run_link import RunTablet
    from app.tablet.serve import TabletServer

    config = load_tablet_config(args.tablet_config)
    tablet = RunTablet(config)
    with TabletServer(tablet, args.host or config.server.host,
                      config.server.port if args.port is None else args.port) as server:
        print(f"tablet: {server.url}  (live view: /mind)", file=sys.stderr, flush=True)
        if server.token:
            print(f"token: {server.token}", file=sys.stderr, flush=True)
        yield tablet
