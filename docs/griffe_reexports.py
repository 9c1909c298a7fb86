"""A griffe extension for the API pages: hullopt's package ``__init__`` files re-export their public names as
``from ._module import name as name`` (no ``__all__``); griffe counts an imported name as private unless
``__all__`` lists it, so this marks such redundant aliases to hullopt's own objects public. The API reference
then shows exactly what ``hullopt.<package>`` exports, as ``tests/test_docs.py`` reads it."""

from __future__ import annotations

from typing import Any

import griffe


class RedundantAliasesArePublic(griffe.Extension):
    """Mark ``from ._x import name as name`` in a package without ``__all__`` public."""

    def on_package(self, *, pkg: griffe.Module, **kwargs: Any) -> None:
        self._visit(pkg)

    def _visit(self, mod: griffe.Module) -> None:
        for name, member in mod.members.items():
            if member.is_alias:
                if (mod.is_init_module and not mod.exports and not name.startswith("_")
                        and member.target_path.startswith("hullopt.")
                        and member.target_path.rsplit(".", 1)[-1] == name):
                    member.public = True
            elif member.is_module:
                self._visit(member)
