"""CLI commands, one module per command family; importing a module registers its commands on the app."""

import importlib

# command name -> the module that defines it (importing only that one keeps a command's start fast)
COMMANDS = {
    "hydro": "hydro", "export": "hydro", "run": "run", "merge": "merge", "features": "features",
    "deform": "features", "waves": "waves", "wind": "wind", "stability": "stability", "lines": "lines",
    "print": "stability", "fair": "fair", "resistance": "resistance", "motions": "motions",
    "report": "report", "rescore": "report",
}


def register(argv: list[str]) -> None:
    """Register the command named first in ``argv`` alone, or every command (for help and usage errors)."""
    name = next((a for a in argv if not a.startswith("-")), None)
    modules = [COMMANDS[name]] if name in COMMANDS else dict.fromkeys(COMMANDS.values())
    for module in modules:
        importlib.import_module(f"{__name__}.{module}")
