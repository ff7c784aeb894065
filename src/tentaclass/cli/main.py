"""The ``tentaclass`` command group: options shared by all commands, errors.

Every expected error (bad input, unreadable files) ends as a one-line message
on stderr and exit code 1 (2 for usage errors), never a traceback.
"""

from __future__ import annotations

import logging
import sys

import click

from .. import __version__
from ..errors import TentaclassError


class _Group(click.Group):
    """Turns library errors into one-line CLI errors."""

    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except (TentaclassError, ValueError, OSError) as exc:
            raise click.ClickException(
                str(exc).splitlines()[0] if str(exc) else repr(exc)
            ) from None
        except MemoryError as exc:
            detail = f": {str(exc).splitlines()[0]}" if str(exc) else ""
            raise click.ClickException(
                f"out of memory{detail} (check sizes and counts given as options or in the input)"
            ) from None


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="tentaclass")
@click.option("-v", "--verbose", count=True, help="More log output on stderr.")
@click.option("-q", "--quiet", is_flag=True, help="Only errors on stderr.")
@click.pass_context
def cli(ctx: click.Context, verbose: int, quiet: bool) -> None:
    """Recognise objects from one-dimensional data arrays.

    Tentacle case: a planar chain's joint angles -> the object's class.
    """
    level = logging.ERROR if quiet else (logging.WARNING - 10 * min(verbose, 2))
    logging.basicConfig(stream=sys.stderr, level=level, format="%(levelname)s: %(message)s")
    ctx.ensure_object(dict)
    ctx.obj["quiet"] = quiet


def _register() -> None:
    from .bench import bench
    from .classify import classify
    from .demo import demo
    from .grasp import grasp
    from .scan import scan
    from .serve import serve
    from .train import train
    from .wrap import wrap

    for command in (bench, classify, demo, grasp, scan, serve, train, wrap):
        cli.add_command(command)


_register()


def main() -> None:
    """Entry point of the ``tentaclass`` script."""
    cli(prog_name="tentaclass")
