"""CLI commands, one module per command family; importing a module registers its commands on the app."""

import importlib
import pkgutil


def register_all() -> None:
    for mod in pkgutil.iter_modules(__path__):
        importlib.import_module(f"{__name__}.{mod.name}")
