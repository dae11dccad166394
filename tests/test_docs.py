"""The README and docs/ are for the people who use the program: every link they hold resolves inside
the repository, and every picture they show exists."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
# [text](target) and ![alt](target); a target ends at whitespace or the closing parenthesis.
_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def _local_targets(document: Path) -> list[str]:
    targets = _LINK.findall(document.read_text(encoding="utf-8"))
    return [target for target in targets if not re.match(r"[a-z]+:", target) and not target.startswith("#")]


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: str(path.relative_to(ROOT)))
def test_every_local_link_resolves_inside_the_repository(document: Path) -> None:
    for target in _local_targets(document):
        resolved = (document.parent / target.split("#", 1)[0]).resolve()
        assert resolved.is_relative_to(ROOT), f"{document.name}: {target} points outside the repository"
        assert resolved.exists(), f"{document.name}: {target} does not exist"


def test_the_readme_links_somewhere() -> None:
    assert len(_local_targets(ROOT / "README.md")) >= 10  # the pattern still finds the README's links
