"""Entry point of the ``hullopt`` command: global JAX set-up, the commands, and one-line errors."""

from __future__ import annotations

import os
import socket
import sys
from pathlib import Path

# XLA logs a false alarm about CPU features each time it loads a cached executable; keep the terminal for
# the user (set TF_CPP_MIN_LOG_LEVEL yourself to see XLA's logs). It must be set before jax is imported.
os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")

from ..errors import HullError  # noqa: E402


def configure_jax() -> None:
    """float64 everywhere, and a per-host persistent compilation cache (warm starts skip compiling)."""
    import jax

    jax.config.update("jax_enable_x64", True)
    cache = Path(os.environ.get("HULLOPT_CACHE", Path.home() / ".cache" / "hullopt")) / f"jax-{socket.gethostname()}"
    try:
        cache.mkdir(parents=True, exist_ok=True)
        jax.config.update("jax_compilation_cache_dir", str(cache))
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
        jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
    except OSError:
        pass  # a read-only home: run without the cache


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; a user's mistake (:class:`HullError`) is one line on stderr and exit code 2."""
    configure_jax()
    from ._app import app
    from .commands import register

    register(sys.argv[1:] if argv is None else argv)
    try:
        app(args=argv)  # usage errors: the parser prints them and exits with code 2
    except SystemExit as e:
        return e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    except HullError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())


def run() -> None:
    """Console-script entry point. Every output is written (atomically) and flushed when :func:`main` returns,
    so the process ends at once: the interpreter's teardown of JAX, XLA and the imported modules would add
    about half a second to every command."""
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
