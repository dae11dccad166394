"""`screenshot -o` never destroys anything: an output that is any input is refused before anything
is read, a picture is written whole or not at all (a temporary file in the same folder, renamed into
place), a symlink at the output is replaced and never followed, the format comes from the suffix,
and every failure is one line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

from support import corpus

MODEL = corpus.TRIANGLE + b"f 1 2 3\n"


def run_app(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "marraztu", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


def assert_refused(result: subprocess.CompletedProcess, *fragments: str) -> None:
    assert result.returncode == 1, result.stderr
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]


def png_bytes() -> bytes:
    return corpus.png_bytes(4, 4)


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "model.obj").write_bytes(MODEL)
    (tmp_path / "photo.png").write_bytes(png_bytes())
    (tmp_path / "scene.toml").write_text('texture = "photo.png"\n[[cameras]]\nmodel = "model.obj"\n'
                                         'position = [0, 0, 150]\n')
    return tmp_path


@pytest.mark.parametrize("args, victim", [
    (["--texture", "photo.png"], "photo.png"),
    (["--scene", "scene.toml"], "photo.png"),  # the scene file's own texture
    (["--keys", "f=photo.png"], "photo.png"),
    (["--texture", "photo.png"], "link.png"),  # a link to an input is that input
])
def test_an_output_that_is_an_input_is_refused_and_left_alone(folder: Path, args: list[str], victim: str) -> None:
    if victim == "link.png":
        (folder / "link.png").symlink_to(folder / "photo.png")
    before = (folder / "photo.png").read_bytes()
    result = run_app("screenshot", "-o", victim, "--size", "16x16", *args, cwd=folder)
    assert_refused(result, victim, "input")
    assert (folder / "photo.png").read_bytes() == before


def test_a_model_cannot_be_overwritten_because_models_are_not_pictures(folder: Path) -> None:
    result = run_app("screenshot", "-o", "model.obj", "model.obj", "--size", "16x16", cwd=folder)
    assert_refused(result, "model.obj")
    assert (folder / "model.obj").read_bytes() == MODEL


def test_a_symlink_at_the_output_is_replaced_not_followed(folder: Path) -> None:
    target = folder / "elsewhere.png"
    target.write_bytes(b"precious")
    (folder / "shot.png").symlink_to(target)
    result = run_app("screenshot", "-o", "shot.png", "--size", "16x16", cwd=folder)
    assert result.returncode == 0, result.stderr
    assert target.read_bytes() == b"precious"
    assert not (folder / "shot.png").is_symlink()
    with Image.open(folder / "shot.png") as picture:
        assert picture.format == "PNG" and picture.size == (16, 16)


def test_a_failed_write_leaves_no_partial_file_and_keeps_the_old_picture(folder: Path) -> None:
    old = folder / "shot.png"
    old.write_bytes(png_bytes())
    before = old.read_bytes()
    os.chmod(folder, 0o555)  # the temporary file cannot be made beside it
    try:
        result = run_app("screenshot", "-o", "shot.png", "--size", "16x16", cwd=folder)
    finally:
        os.chmod(folder, 0o755)
    if corpus.running_as_root():
        assert result.returncode == 0, result.stderr  # root writes anyway: the picture is whole
        with Image.open(old) as picture:
            assert picture.size == (16, 16)
    else:
        assert_refused(result, "shot.png", "cannot write")
        assert old.read_bytes() == before
    assert not [path for path in folder.iterdir() if path.name.endswith(".part")]


@pytest.mark.parametrize("name", ["pipe.png", "dir.png"])
def test_a_fifo_or_a_folder_at_the_output_is_refused(folder: Path, name: str) -> None:
    path = folder / name
    if name == "pipe.png":
        os.mkfifo(path)
    else:
        path.mkdir()
    result = run_app("screenshot", "-o", name, "--size", "16x16", cwd=folder)
    assert_refused(result, name)
    assert path.is_fifo() if name == "pipe.png" else path.is_dir()


@pytest.mark.parametrize("suffix, kind", [(".png", "PNG"), (".PNG", "PNG"), (".jpg", "JPEG"), (".jpeg", "JPEG")])
def test_the_format_follows_the_suffix(folder: Path, suffix: str, kind: str) -> None:
    result = run_app("screenshot", "-o", f"shot{suffix}", "--size", "16x8", cwd=folder)
    assert result.returncode == 0, result.stderr
    with Image.open(folder / f"shot{suffix}") as picture:
        assert picture.format == kind and picture.size == (16, 8)


@pytest.mark.parametrize("output", ["shot.gif", "shot", "/dev/full"])
def test_an_unknown_suffix_is_refused(folder: Path, output: str) -> None:
    assert_refused(run_app("screenshot", "-o", output, "--size", "16x16", cwd=folder), ".png, .jpg")



def test_a_picture_read_upside_down_is_put_upright_without_a_copy_of_it(tmp_path: Path) -> None:
    """read_pixels turns GL's rows over in a view; Pillow's fromarray copied such a view whole before its
    own copy (at 16384x16384, 805 MB more at the screenshot command's peak)."""
    import tracemalloc

    import numpy as np

    from marraztu.frontends.screenshot import picture_of, write_picture

    rows = np.random.default_rng(1).integers(0, 256, (600, 500, 3), np.uint8)
    stored = np.frombuffer(rows[::-1].tobytes(), np.uint8).reshape(rows.shape)  # as GL gives them
    tracemalloc.start()
    try:
        picture = picture_of(np.flipud(stored))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < rows.nbytes / 4
    assert np.array_equal(np.asarray(picture), rows)
    assert np.array_equal(np.asarray(picture_of(rows)), rows)  # an array upright already
    write_picture(np.flipud(stored), tmp_path / "picture.png")
    assert np.array_equal(np.asarray(Image.open(tmp_path / "picture.png").convert("RGB")), rows)
