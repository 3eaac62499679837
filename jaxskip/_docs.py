"""``help()`` for the library's dataclasses: their fields' units and shapes.

Each field of a state or settings class is documented where it is declared, by the string literal
after it (the convention of Equinox and diffrax). Sphinx reads those strings; ``help()`` does not, so
:func:`document_fields` appends them to the class docstring once, when the class is defined.
"""

from __future__ import annotations

import ast
import functools
import inspect
import textwrap


@functools.lru_cache(maxsize=None)
def _class_nodes(path: str) -> dict:
    """The top-level class definitions of the module at ``path`` by name (each module parsed once)."""
    try:
        with open(path, encoding="utf-8") as fh:
            tree = ast.parse(fh.read())
    except (OSError, SyntaxError, ValueError):
        return {}
    return {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}


def document_fields(cls):
    """Class decorator: append a "Fields" section (each field's own docstring) to ``cls.__doc__``.

    >>> from jaxskip import Throw
    >>> print(Throw.__doc__.split("Fields")[1].splitlines()[2:4])
    ['speed', '    () speed of the centre of mass [m/s], in (0, 100].']
    """
    definition = _class_nodes(inspect.getsourcefile(cls) or "").get(cls.__name__)
    if definition is None:  # no source (frozen, interactive): leave the docstring as it is
        return cls
    body = definition.body
    entries = []
    for node, after in zip(body, body[1:]):
        if (isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name)
                and isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant)
                and isinstance(after.value.value, str)):
            text = textwrap.indent(inspect.cleandoc(after.value.value), "    ")
            entries.append(f"{node.target.id}\n{text}")
    if entries:
        cls.__doc__ = (inspect.cleandoc(cls.__doc__ or cls.__name__) + "\n\nFields\n------\n" + "\n".join(entries))
    return cls
