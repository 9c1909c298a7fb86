"""``python -m hullopt`` runs the CLI."""

from hullopt.app.cli import run

if __name__ == "__main__":  # not in a process that multiprocessing's spawn starts (it imports this as __mp_main__)
    run()
