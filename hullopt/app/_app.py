"""The Typer application object; command modules in ``commands/`` register themselves on it.

Help texts are plain text: units in brackets (``help="Ship speed [kn]."``) must not be read as rich markup
(rich would print ``Ship speed .``). Every command registered with ``@app.command()`` gets the
:class:`PlainHelpCommand` class, which escapes its help, its parameters' help and its epilog once, here. A command
that reads a hull takes ``strict: Strict = False`` (``--strict``: its hull's plausibility warnings refused)."""

from __future__ import annotations

import inspect
import warnings
from importlib.metadata import PackageNotFoundError, version
from typing import Annotated

import typer
from rich.markup import escape
from typer.core import HAS_RICH, TyperCommand, TyperGroup

from ..errors import HullWarning
from ..report import JSON_UNITS
from .output import exit_code_help

HELP = "Differentiable hull-form optimiser: hydrostatics, added resistance, wind, fitting, fairing."
EPILOG = f"{JSON_UNITS}\n\n{exit_code_help()}"


def _plain(text: str | None) -> str | None:
    """``text`` escaped for rich markup (where typer reads help as rich markup), so it prints as written."""
    return escape(text) if text and HAS_RICH else text


def _reflow(text: str | None) -> str | None:
    """Each paragraph of a docstring on one line (rich wraps it to the terminal; typer's rich mode would keep
    the source's line breaks); a paragraph marked ``\\b`` (click: no rewrapping) kept as written."""
    if not text:
        return text
    paragraphs = inspect.cleandoc(text).split("\n\n")
    return "\n\n".join(p if p.startswith("\b") else " ".join(p.split()) for p in paragraphs)


def _escape_help(cmd) -> None:
    cmd.help, cmd.epilog = _reflow(cmd.help), _reflow(cmd.epilog)
    if not cmd.short_help and cmd.help:  # the list of commands: the first paragraph
        cmd.short_help = cmd.help.split("\n\n")[0]
    cmd.help, cmd.epilog, cmd.short_help = _plain(cmd.help), _plain(cmd.epilog), _plain(cmd.short_help)
    for p in cmd.params:
        if getattr(p, "help", None):
            p.help = _plain(p.help)


class PlainHelpCommand(TyperCommand):
    """A command whose help texts print as written (units in brackets kept)."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        _escape_help(self)


STRICT_HELP = ("Refuse a hull that looks implausible (a mesh in millimetres, in the wrong axes, upside down): "
               "its warning becomes a one-line error (exit code 2).")


def _strict(value: bool) -> bool:
    """``--strict``: every :class:`~hullopt.errors.HullWarning` of this command raised as an error (the CLI's
    ``main`` prints it as one line, exit code 2, and restores the warning filters after the command)."""
    if value:
        warnings.simplefilter("error", HullWarning)
    return value


#: ``--strict``, the option of every command that reads a hull (``strict: Strict = False``): set while the
#: arguments are parsed, before the command runs, so the command's body never reads it (not passed).
Strict = Annotated[bool, typer.Option("--strict", help=STRICT_HELP, callback=_strict, expose_value=False)]


class PlainHelpGroup(TyperGroup):
    """The ``hullopt`` group, its help and options printed as written."""

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        _escape_help(self)


class _Typer(typer.Typer):
    def command(self, *args, **kwargs):
        kwargs.setdefault("cls", PlainHelpCommand)
        return super().command(*args, **kwargs)


app = _Typer(
    name="hullopt",
    cls=PlainHelpGroup,
    help=HELP,
    epilog=EPILOG,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def package_version() -> str:
    """hullopt's version from the installed package's metadata ('unknown' when it is not installed)."""
    try:
        return version("hullopt")
    except PackageNotFoundError:
        return "unknown"


def _version(value: bool) -> bool:
    if value:
        print(f"hullopt {package_version()}")
        raise typer.Exit(0)
    return value  # click keeps a callback's return as the option's value


@app.callback()
def _main(
    show_version: Annotated[bool, typer.Option("--version", callback=_version, is_eager=True,
                                               help="Print hullopt's version and exit.")] = False,
) -> None:
    """Differentiable hull-form optimiser: hydrostatics, added resistance, wind, fitting, fairing."""
    # A callback keeps the app a group of commands even when only the invoked command is registered.
