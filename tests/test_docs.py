"""The README and docs/ are for the people who use the program: every link they hold resolves inside
the repository, every picture they show exists, and the README's Python and scene file run as written."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import trimesh
from PIL import Image

from marraztu.resources import ASSET_DIR

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


def _slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, blanks made hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


@pytest.mark.parametrize("document", DOCUMENTS, ids=lambda path: str(path.relative_to(ROOT)))
def test_every_anchor_names_a_heading_of_its_document(document: Path) -> None:
    text = document.read_text(encoding="utf-8")
    headings = {_slug(heading) for heading in re.findall(r"^#+ (.*)$", text, re.MULTILINE)}
    for target in _LINK.findall(text):
        if target.startswith("#"):
            assert target[1:] in headings, f"{document.name}: {target} names no heading"


def test_the_readme_links_somewhere() -> None:
    assert len(_local_targets(ROOT / "README.md")) >= 10  # the pattern still finds the README's links


def test_the_readmes_python_runs_as_written_given_its_two_files(tmp_path: Path, monkeypatch, capsys) -> None:
    """It used positions, faces and trimesh without a word of where they came from: a NameError."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    code = re.search(r"### From Python and notebooks.*?```python\n(.*?)```", text, re.DOTALL).group(1)
    for name, given in (("model.obj", "crate.obj"), ("crate.mtl", "crate.mtl"), ("crate.ppm", "crate.ppm")):
        (tmp_path / name).write_bytes((ASSET_DIR / "examples" / given).read_bytes())
    trimesh.creation.icosphere(radius=30.0).export(tmp_path / "duck.glb")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    with Image.open(tmp_path / "shot.png") as shot:  # .size reads the header only: the file stays open
        assert shot.size == (800, 600)
    assert capsys.readouterr().out.startswith("everything ")


def test_the_readmes_scene_file_loads_as_written_beside_its_models(tmp_path: Path) -> None:
    """The Files section's TOML, with the models and texture it names beside it, is a scene the viewer
    opens without a word of complaint."""
    import marraztu

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    scene = re.search(r"```toml\n(.*?)```", text, re.DOTALL).group(1)
    (tmp_path / "my.toml").write_text(scene, encoding="utf-8")
    for name in ("camera.obj", "rammer.obj", "selfi.ppm"):
        (tmp_path / name).write_bytes((ASSET_DIR / name).read_bytes())
    (tmp_path / "concrete.png").write_bytes((ROOT / "docs" / "screenshots" / "start.png").read_bytes())
    with marraztu.Viewer(size=(64, 48), scene=tmp_path / "my.toml") as viewer:
        assert [obj.name for obj in viewer.scene.objects] == ["Rammer_255"]
        assert viewer.scene.objects[0].material.ns == 10
        assert viewer.scene.objects[0].picture is not None
        assert "checker" not in viewer.message


def test_the_readmes_lights_load_as_written(tmp_path: Path) -> None:
    """The Files section's second TOML, the lights, is a scene of its own: the built-in camera, lit so."""
    import marraztu

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    lights = re.findall(r"```toml\n(.*?)```", text, re.DOTALL)[1]
    (tmp_path / "lights.toml").write_text(lights, encoding="utf-8")
    with marraztu.Viewer(size=(64, 48), scene=tmp_path / "lights.toml") as viewer:
        assert [light.on for light in viewer.scene.lights] == [True, True, False, False]
        assert viewer.scene.lights[2].aperture_deg == 25.75


def _keys_table_tokens(text: str) -> set[str]:
    """The key map's tokens of the README's keys table: `a` `b`, `x y z` and named keys as written."""
    section = text[text.index("### Keys"):text.index("| mouse | does |")]
    cells = re.findall(r"^\| (?!key \|)([^|]+?) \|", section, re.MULTILINE)
    named = {"Enter": "ENTER", "PageDown": "PAGEDOWN", "PageUp": "PAGEUP"}
    tokens: set[str] = set()
    for cell in cells:
        for word in cell.replace("`", " ").replace("/", " ").split():
            tokens.add(named.get(word, word))
    return tokens - {"---"}


def test_the_readmes_keys_table_lists_every_key_of_the_key_map_and_no_other() -> None:
    """It left out h and F1, named only in the sentence above it."""
    from marraztu.control.keymap import KEYMAP

    assert _keys_table_tokens((ROOT / "README.md").read_text(encoding="utf-8")) == set(KEYMAP)
