"""Regular expressions whose possessive repeats of groups hold on every Python 3.11.

CPython 3.11.0 to 3.11.4, Debian 12's python3 among them, match a possessive repeat of a group
wrongly where one repetition fails partway (CPython gh-106052, fixed in 3.11.5): `(?:v +[0-9]+\\n)*+`
run over "v 1\\nvt 0\\n" ends after the v of "vt", and the OBJ reader lost that file's first vt line.
There, `compiled` builds each such repeat as the atomic group of a greedy one, which is its documented
meaning. Elsewhere it is `re.compile`: the possessive repeat keeps no state per repetition, where the
atomic group keeps some (150 MB for a run of two million digits).
"""

from __future__ import annotations

import re
import sys
from typing import AnyStr

POSSESSIVE_GROUPS_HOLD = sys.version_info >= (3, 11, 5)


def compiled(pattern: AnyStr, flags: int = 0) -> re.Pattern[AnyStr]:
    """re.compile(pattern, flags), with its possessive repeats of groups made atomic groups where
    this Python matches them wrongly."""
    return re.compile(pattern, flags) if POSSESSIVE_GROUPS_HOLD else atomic_compiled(pattern, flags)


def atomic_compiled(pattern: AnyStr, flags: int = 0) -> re.Pattern[AnyStr]:
    """The pattern compiled with every possessive repeat of more than one character, X*+, X++, X?+
    or X{m,n}+, compiled as (?>X*), (?>X+), (?>X?) or (?>X{m,n}): the same matches."""
    import _sre  # Python's own re internals, read only on the Pythons that need the rewrite
    from re import _compiler, _parser

    tree = _parser.parse(pattern, flags)
    _make_atomic(tree)
    groups = tree.state.groupdict
    names: list[str | None] = [None] * tree.state.groups
    for name, index in groups.items():
        names[index] = name
    return _sre.compile(pattern, flags | tree.state.flags, _compiler._code(tree, flags), tree.state.groups - 1,
                        groups, tuple(names))


def _make_atomic(tree: object) -> None:
    from re import _compiler, _constants, _parser

    data = tree.data  # type: ignore[attr-defined]
    for at, (op, value) in enumerate(data):
        if op is _constants.POSSESSIVE_REPEAT and not _compiler._simple(value[2]):
            _make_atomic(value[2])
            data[at] = (_constants.ATOMIC_GROUP,
                        _parser.SubPattern(tree.state, [(_constants.MAX_REPEAT, value)]))  # type: ignore[attr-defined]
            continue
        for part in _parts(value):
            _make_atomic(part)


def _parts(value: object) -> list[object]:
    """The subpatterns a node holds."""
    from re import _parser

    found: list[object] = []
    stack = [value]
    while stack:
        item = stack.pop()
        if isinstance(item, _parser.SubPattern):
            found.append(item)
        elif isinstance(item, (tuple, list)):
            stack.extend(item)
    return found
