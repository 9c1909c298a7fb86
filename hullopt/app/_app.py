"""The Typer application object; command modules in ``commands/`` register themselves on it."""

import typer

app = typer.Typer(
    name="hullopt",
    help="Differentiable hull-form optimiser: hydrostatics, added resistance, wind, fitting, fairing.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@app.callback()
def _main() -> None:
    """Differentiable hull-form optimiser: hydrostatics, added resistance, wind, fitting, fairing."""
    # A callback keeps the app a group of commands even when only the invoked command is registered.
