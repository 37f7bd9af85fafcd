"""EnumProperty items built from the core's bound enumerations (``am._core.LaplacianMethod``
and the like), so the add-on offers exactly the choices the core accepts and never lists
them itself."""

from __future__ import annotations


def enum_items(enum, texts: dict[str, tuple[str, str]], upper: bool = False) -> tuple[tuple[str, str, str], ...]:
    """(identifier, label, description) for every member of the bound `enum`, in the core's
    order. `texts` gives each name its label and description; a name the add-on has no text
    for still appears, titled. `upper`: identifiers in upper case (the operators whose items
    have always been so), else the core's names."""
    return tuple(((name.upper() if upper else name),
                  *texts.get(name, (name.replace("_", " ").title(), f"The core's '{name}'")))
                 for name in enum.__members__)
