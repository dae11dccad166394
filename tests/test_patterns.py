"""The readers' possessive repeats of groups, which CPython 3.11.0 to 3.11.4 (Debian 12's python3)
match wrongly (gh-106052): there every such pattern is compiled as its atomic-group equivalent."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap

import pytest

from marraztu.loaders.patterns import atomic_compiled


@pytest.mark.parametrize(("pattern", "atomic", "text", "span"), [
    (rb"(?:v[ ]+[0-9]+\n)*+", rb"(?>(?:v[ ]+[0-9]+\n)*)", b"v 1\nvt 0\n", (0, 4)),  # 3.11.2's re: (0, 5)
    (r"(?:ab?c)*+", r"(?>(?:ab?c)*)", "a", (0, 0)),  # the CPython issue's own case; 3.11.2's re: (0, 1)
    (r"(?:_?+[0-9]){3,}+x", r"(?>(?:_?+[0-9]){3,})x", "1_23x", (0, 5)),
    (r"(?P<word>(?:b|bc)++)c", r"(?P<word>(?>(?:b|bc)+))c", "bcbcc", (0, 2)),  # the first b, never bc
    (r"(?:\.[0-9]*+)?+5", r"(?>(?:\.[0-9]*+)?)5", ".5", None),  # the group takes the 5, gives nothing back
])
def test_a_possessive_repeat_of_a_group_is_its_atomic_group(pattern, atomic, text, span) -> None:
    made = atomic_compiled(pattern)
    assert [found and found.span() for found in (made.match(text), re.match(atomic, text))] == [span, span]
    assert made.pattern == pattern
    assert made.groupindex == re.compile(pattern).groupindex


def test_every_possessive_group_in_the_readers_is_compiled_to_hold() -> None:
    """Run as on a Python that needs it (any Python here): every module-level pattern of the readers that
    repeats a group possessively was made by patterns.compiled, and the built-in scene's OBJ reads whole."""
    script = textwrap.dedent("""
        import importlib, pkgutil, re
        from re import _compiler, _constants, _parser
        import marraztu.loaders.patterns as patterns
        patterns.POSSESSIVE_GROUPS_HOLD = False
        import marraztu.loaders

        def possessive_groups(tree):
            for op, value in tree.data:
                if op is _constants.POSSESSIVE_REPEAT and not _compiler._simple(value[2]):
                    return True
                stack = [value]
                while stack:
                    item = stack.pop()
                    if isinstance(item, _parser.SubPattern) and possessive_groups(item):
                        return True
                    if isinstance(item, (tuple, list)):
                        stack.extend(item)
            return False

        def patterns_in(value, depth=0):
            if isinstance(value, re.Pattern):
                yield value
            elif depth < 6 and isinstance(value, (tuple, list, dict)):
                for item in (value.values() if isinstance(value, dict) else value):
                    yield from patterns_in(item, depth + 1)

        missed, seen = [], 0
        for module in pkgutil.walk_packages(marraztu.loaders.__path__, "marraztu.loaders."):
            for name, value in vars(importlib.import_module(module.name)).items():
                for pattern in patterns_in(value):
                    if possessive_groups(_parser.parse(pattern.pattern, pattern.flags)):
                        seen += 1
                        if pattern == re.compile(pattern.pattern, pattern.flags):
                            missed.append(f"{module.name}.{name}")
        print(seen, sorted(set(missed)))

        from marraztu.loaders.obj.lines import read_by_lines
        from marraztu.resources import ASSET_DIR
        text = (ASSET_DIR / "x_wing.obj").read_bytes()
        print(text.count(b"\\nvt "), len(read_by_lines(text, "x_wing.obj").texcoords))
    """)
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    seen, missed, lines, read = result.stdout.split(maxsplit=3)
    assert int(seen) > 10 and missed == "[]"
    assert int(lines) == int(read) > 500
