"""``python -m hullopt`` runs the CLI."""

from hullopt.app.cli import run

run()
