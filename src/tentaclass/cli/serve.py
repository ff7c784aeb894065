"""``tentaclass serve``: the drawing page and its JSON API on a local web server."""

from __future__ import annotations

import socket
from pathlib import Path

import click


@click.command()
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Address to listen on (127.0.0.1: this computer only).")  # fmt: skip
@click.option("--port", type=click.IntRange(0, 65535), default=8000, show_default=True)
@click.option("--data-dir", type=click.Path(file_okay=False, path_type=Path),
              help="Folder for taught shapes and the model file (default: in memory).")  # fmt: skip
def serve(host: str, port: int, data_dir: Path | None) -> None:
    """Serve the page to draw objects, wrap a tentacle around them and name them.

    Open the printed address in a browser; the JSON API is documented at /docs.
    Needs the web extra: pip install 'tentaclass[web]'.
    """
    from .._lazy import import_extra

    needs = "the web page needs the 'web' extra"
    for module in ("uvicorn", "tentaclass.web._app"):
        import_extra(module, "web", needs, error=click.ClickException)
    import uvicorn

    from ..web import create_app

    shown = f"[{host}]" if ":" in host else host

    class AnnouncingServer(uvicorn.Server):
        """A uvicorn server that prints the address it listens on once it does."""

        async def startup(self, sockets: list[socket.socket] | None = None) -> None:
            await super().startup(sockets=sockets)
            if self.started:
                bound = port
                for s in self.servers:
                    for sock in s.sockets:
                        bound = sock.getsockname()[1]
                click.echo(f"tentaclass serving on http://{shown}:{bound}/ (API docs at /docs)")

    app = create_app(data_dir)
    config = uvicorn.Config(app, host=host, port=port, log_level="warning")
    AnnouncingServer(config).run()
