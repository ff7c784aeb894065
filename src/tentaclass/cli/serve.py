"""``tentaclass serve``: the drawing page and its JSON API on a local web server."""

from __future__ import annotations

import errno
import ipaddress
import os
import re
import socket
from pathlib import Path

import click

from .options import Folder

#: Hosts made of digits and dots only: IPv4 addresses, which the resolver would
#: otherwise also read in the short forms "300" (0.0.1.44) or "10.1" (10.0.0.1).
_DOTTED = re.compile(r"^[\d.]+$")


def listening_socket(host: str, port: int) -> socket.socket:
    """A TCP socket bound to ``host:port`` for the server, or a one-line ClickException.

    ``host`` is an IPv4 or IPv6 address (brackets allowed) or a name;
    port 0 picks a free port. An empty or malformed address is a usage error
    (exit code 2, as a port out of range is); a name that does not resolve or
    an address this computer cannot listen on is an error of exit code 1.
    """
    name = host.strip()
    if name.startswith("[") and name.endswith("]"):
        name = name[1:-1]
    if not name:
        raise click.UsageError("--host is empty: give an address such as 127.0.0.1 or 0.0.0.0")
    if _DOTTED.match(name):
        try:
            ipaddress.IPv4Address(name)
        except ValueError:
            raise click.UsageError(
                f"--host {host!r} is not an IPv4 address (four numbers 0-255 such as 127.0.0.1)"
            ) from None
    family = socket.AF_INET6 if ":" in name else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        if os.name != "nt":  # on Windows it would let two servers share the port
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((name, port))
    except socket.gaierror as exc:
        sock.close()
        raise click.ClickException(f"--host {host!r}: no such host ({exc.strerror})") from None
    except OSError as exc:
        sock.close()
        why = exc.strerror or str(exc)
        if exc.errno == errno.EADDRINUSE:
            why += " (another server listens there: choose another --port, or 0 for a free one)"
        elif exc.errno == errno.EADDRNOTAVAIL:
            why += " (not an address of this computer)"
        raise click.ClickException(f"cannot listen on {name}:{port}: {why}") from None
    sock.set_inheritable(True)
    return sock


@click.command()
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Address to listen on (127.0.0.1: this computer only).")  # fmt: skip
@click.option("--port", type=click.IntRange(0, 65535), default=8000, show_default=True)
@click.option("--data-dir", type=Folder(),
              help="Folder for taught shapes and the model file (default: in memory).")  # fmt: skip
def serve(host: str, port: int, data_dir: Path | None) -> None:
    """Serve the page to draw objects, wrap a tentacle around them and name them.

    Open the printed address in a browser; the JSON API is documented at /docs.
    Needs the web extra: pip install 'tentaclass[web]'.
    """
    sock = listening_socket(host, port)  # first: a bad address fails at once
    name, bound = sock.getsockname()[:2]
    shown = f"[{name}]" if ":" in name else name
    with sock:
        from .._lazy import import_extra

        needs = "the web page needs the 'web' extra"
        for module in ("uvicorn", "tentaclass.web._app"):
            import_extra(module, "web", needs, error=click.ClickException)
        import uvicorn

        from ..web import create_app

        class AnnouncingServer(uvicorn.Server):
            """A uvicorn server that prints the address it listens on once it does."""

            async def startup(self, sockets: list[socket.socket] | None = None) -> None:
                await super().startup(sockets=sockets)
                if self.started:
                    click.echo(f"tentaclass serving on http://{shown}:{bound}/ (API docs at /docs)")

        config = uvicorn.Config(create_app(data_dir), host=name, port=bound, log_level="warning")
        AnnouncingServer(config).run(sockets=[sock])
