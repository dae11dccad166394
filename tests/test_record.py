"""`marraztu record`: one frame per press, the first and last equal to the screenshots of the same key
prefixes (exactly in animated PNG, to GIF's 256 colours in GIF), and bad input refused in one line as
the screenshot command refuses it."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from marraztu.cli import main
from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot

SIZE = "160x120"
KEYS = "0 1 y*5"


def frames_of(path: Path) -> tuple[list[np.ndarray], dict]:
    with Image.open(path) as animation:
        info = dict(animation.info)
        return [np.asarray(frame.convert("RGB")).astype(int) for frame in ImageSequence.Iterator(animation)], info


def frame_ms(fps: int) -> int:
    """The frame time an animation file states for --fps: a number written into it, nothing timed."""
    return 1000 // fps


def stated_frame_ms(info: dict) -> int:
    """The per-frame delay the file declares (Pillow's 'duration'): metadata written from --fps."""
    return info["duration"]


def screenshot(tmp_path: Path, keys: str) -> np.ndarray:
    out = take_screenshot(StartOptions(), tmp_path / f"shot{len(keys)}.png", (160, 120), keys=keys)
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


def test_one_frame_is_said_as_one(tmp_path: Path, capsys) -> None:
    """record said '1 frames'."""
    assert main(["record", "-o", str(tmp_path / "one.png"), "--size", "16x16", "--keys", "y"]) == 0
    assert capsys.readouterr().out.rstrip().endswith(": 1 frame")


@pytest.mark.parametrize("name", ["same.gif", "same.png"])
def test_frames_all_alike_are_said_to_be(tmp_path: Path, capsys, name: str) -> None:
    """'63 frames' was said of presses that moved nothing in view, and the GIF held one picture."""
    out = tmp_path / name
    assert main(["record", "-o", str(out), "--size", "16x16", "--empty", "--keys", "y*3"]) == 0
    assert capsys.readouterr().out.rstrip().endswith(
        ": 3 frames, all the same picture: the keys changed nothing in view")
    assert len(frames_of(out)[0]) == (1 if name.endswith(".gif") else 3)


def test_a_gif_says_how_many_pictures_it_holds_where_frames_repeat(tmp_path: Path, capsys) -> None:
    """Pillow joins a GIF's frame to the one before where they are alike: the file holds fewer than said."""
    out = tmp_path / "repeats.gif"
    assert main(["record", "-o", str(out), "--size", "32x24", "--keys", "y y h y"]) == 0  # h: a panel not drawn
    assert capsys.readouterr().out.rstrip().endswith(": 4 frames, held as 3 pictures: a GIF shows a frame "
                                                     "the same as the one before by showing that one longer")
    assert len(frames_of(out)[0]) == 3


def test_animated_png_holds_one_exact_frame_per_press(tmp_path: Path, capsys) -> None:
    out = tmp_path / "turn.png"
    assert main(["record", "-o", str(out), "--size", SIZE, "--keys", KEYS, "--fps", "20"]) == 0
    assert "7 frames" in capsys.readouterr().out
    frames, info = frames_of(out)
    assert len(frames) == 7
    assert stated_frame_ms(info) == frame_ms(20)
    assert np.array_equal(frames[0], screenshot(tmp_path, "0"))
    assert np.array_equal(frames[-1], screenshot(tmp_path, KEYS))
    assert not np.array_equal(frames[2], frames[3]), "each press turns the object"


def test_keys_before_are_pressed_but_not_recorded(tmp_path: Path, capsys) -> None:
    """The set-up keys (lights on, a shading) were the slide's first frames, a dark one first: --before
    presses them through the same replay, drawing nothing."""
    out = tmp_path / "turn.png"
    assert main(["record", "-o", str(out), "--size", SIZE, "--before", "0 1", "--keys", "y*5"]) == 0
    assert "5 frames" in capsys.readouterr().out
    frames, _ = frames_of(out)
    assert len(frames) == 5
    assert np.array_equal(frames[0], screenshot(tmp_path, "0 1 y"))
    assert np.array_equal(frames[-1], screenshot(tmp_path, KEYS))


def test_keys_type_into_a_prompt_that_before_left_open(tmp_path: Path) -> None:
    """--before "f" then --keys typing a file name and ENTER was refused ("unknown key '/'"), the keys
    read as if the prompt were shut. Now they type the name, and the load is the recording's frame."""
    model = tmp_path / "e.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    out = tmp_path / "load.png"
    keys = " ".join([*str(model), "ENTER"])
    assert main(["record", "-o", str(out), "--size", "16x16", "--before", "f", "--keys", keys]) == 0
    assert len(frames_of(out)[0]) == len(str(model)) + 1


def test_before_keys_may_start_with_a_minus(tmp_path: Path) -> None:
    """As --keys "-*5": the value is the key `-`, not an option, after --before and its prefix --b."""
    for option in ("--before", "--b"):
        out = tmp_path / f"{option.strip('-')}.png"
        assert main(["record", "-o", str(out), "--size", "16x16", option, "-*3", "--keys", "y"]) == 0
        assert len(frames_of(out)[0]) == 1


def test_a_gifs_frame_time_is_rounded_to_its_hundredths(tmp_path: Path) -> None:
    """Pillow truncated 1000/35 ms to 20 ms: 50 frames a second for 35."""
    out = tmp_path / "turn.gif"
    assert main(["record", "-o", str(out), "--size", "16x16", "--keys", "y y", "--fps", "35"]) == 0
    assert stated_frame_ms(frames_of(out)[1]) == 30


def test_gif_frames_match_to_its_colours(tmp_path: Path) -> None:
    out = tmp_path / "turn.gif"
    assert main(["record", "-o", str(out), "--size", SIZE, "--keys", KEYS, "--fps", "10"]) == 0
    frames, info = frames_of(out)
    assert len(frames) == 7 and stated_frame_ms(info) == frame_ms(10)
    for frame, keys in ((frames[0], "0"), (frames[-1], KEYS)):
        difference = np.abs(frame - screenshot(tmp_path, keys))
        assert difference.mean() < 1.0 and (difference.max(axis=2) > 16).mean() < 0.01


@pytest.mark.parametrize(("arguments", "words"), [
    (["-o", "{tmp}/turn.txt", "--keys", "y"], "write an animation as .gif"),
    (["-o", "{tmp}/turn.gif", "--keys", ""], "one frame is drawn after each press"),
    (["-o", "{tmp}", "--keys", "y"], "write an animation"),
    (["-o", "{tmp}/turn.gif", "--keys", "y*2000", "--size", "1000x1000"], "GiB"),
    (["-o", "{tmp}/model.png", "--keys", "y", "--texture", "{tmp}/model.png"], "is an input"),
    (["-o", "/dev/full/x.gif", "--keys", "y"], "/dev/full is not a folder"),
    (["-o", "{tmp}/turn.gif", "--keys", "y", "--fps", "60"], "a GIF plays at most 50 frames a second"),
    (["-o", "{tmp}/turn.mp4", "--keys", "y", "--size", "1x50"], "an MP4's sides are at least 2 pixels"),
    (["-o", "{tmp}/still.gif", "--keys", "c*14", "--size", "16x16", "--fps", "0.02"], "at most 655 s"),
    (["-o", "{tmp}/turn.gif", "--before", "0 NOSUCHKEY", "--keys", "y"], "--before: unknown key 'NOSUCHKEY'"),
    (["-o", "{tmp}/turn.gif", "--before", "'f=unclosed", "--keys", "y"], "--before: key sequence"),
    (["-o", "{tmp}/model.png", "--before", "f={tmp}/model.png", "--keys", "y"], "is an input"),
])
def test_bad_input_is_one_line(tmp_path: Path, capsys, arguments: list[str], words: str) -> None:
    Image.new("RGB", (4, 4)).save(tmp_path / "model.png")
    assert main(["record", *(a.format(tmp=tmp_path) for a in arguments)]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error:") and "\n" not in error and words in error, error
    assert not list(tmp_path.glob("*.gif")), "nothing half-written is left behind"


# Keys of --before refused as they ran said nothing of --before: "error: f: cannot load a file while lights
# are targeted" read as a key of --keys; ESC in --before said "the keys quit before the first one was drawn".
BEFORE_REFUSED = [
    ("c c f", "f: cannot load a file while lights are targeted"),
    ("click=500,500", "click=500,500 lies outside the 16x16 picture"),
    ("f={tmp}/missing.obj", "missing.obj: no such file"),
    ("f a ENTER", "a: no such file"),
    ("ESC", "ESC quits"),
]


@pytest.mark.parametrize(("before", "words"), BEFORE_REFUSED, ids=[before for before, _ in BEFORE_REFUSED])
def test_a_key_of_before_refused_as_it_runs_says_it_is_of_before(tmp_path: Path, capsys, before: str,
                                                                 words: str) -> None:
    arguments = ["-o", str(tmp_path / "turn.gif"), "--size", "16x16", "--before", before.format(tmp=tmp_path),
                 "--keys", "y"]
    assert main(["record", *arguments]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error: --before: ") and "\n" not in error and words in error, error
    assert not list(tmp_path.glob("*.gif"))


@pytest.mark.parametrize("before", ["f={tmp}/turn.png", "f={tmp}/./turn.png", "x f={tmp}/m.obj"])
def test_a_key_of_before_loading_the_output_says_it_is_of_before(tmp_path: Path, capsys, before: str) -> None:
    """f=OUT in --before was refused without the '--before: ' its other refusals carry; a model whose
    texture is OUT, read as --before runs, had it."""
    Image.new("RGB", (4, 4)).save(tmp_path / "turn.png")
    (tmp_path / "m.mtl").write_text("newmtl a\nmap_Kd turn.png\n")
    (tmp_path / "m.obj").write_text("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n")
    written = (tmp_path / "turn.png").read_bytes()
    arguments = ["-o", str(tmp_path / "turn.png"), "--size", "16x16", "--before", before.format(tmp=tmp_path),
                 "--keys", "y"]
    assert main(["record", *arguments]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error: --before: ") and "\n" not in error and "is an input" in error, error
    assert (tmp_path / "turn.png").read_bytes() == written


@pytest.mark.parametrize(("keys", "words"), [(before, words) for before, words in BEFORE_REFUSED if before != "ESC"])
def test_a_key_of_keys_refused_as_it_runs_says_what_it_said(tmp_path: Path, capsys, keys: str, words: str) -> None:
    arguments = ["-o", str(tmp_path / "turn.gif"), "--size", "16x16", "--before", "x", "--keys",
                 keys.format(tmp=tmp_path)]
    assert main(["record", *arguments]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error: ") and words in error and "--before" not in error, error


@pytest.mark.parametrize(("before", "keys", "hint"), [("f", "xyz", True), ("f", "ESC f xyz", False),
                                                      ("", "f xyz", False), ("f", "x*0", False)])
def test_a_word_the_prompt_refuses_says_where_before_left_it_open(tmp_path: Path, capsys, before: str, keys: str,
                                                                  hint: bool) -> None:
    """--before "f" --keys "xyz" said "'xyz' in the file prompt", where --keys opened none; a prompt
    --keys opens, and a word refused wherever it stands, say what they said."""
    arguments = ["-o", str(tmp_path / "turn.gif"), "--size", "16x16", "--before", before, "--keys", keys]
    assert main(["record", *arguments]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith(f"error: {keys.split()[-1]!r}") and "\n" not in error, error
    assert error.endswith(" (--before left the file prompt open)") == hint, error


# 0.001: a frame past 65.535 s, an animated PNG's longest
@pytest.mark.parametrize("fps", ["0", "-1", "0.001", "1e-308", "1e9", "nan", "inf", "abc"])
def test_fps_out_of_range_is_a_usage_error(tmp_path: Path, capsys, fps: str) -> None:
    """As --size 0x5 is: exit status 2 and argparse's one line, before anything is drawn."""
    with pytest.raises(SystemExit) as stop:
        main(["record", "-o", str(tmp_path / "turn.png"), "--keys", "y y", "--fps", fps])
    error = capsys.readouterr().err
    assert stop.value.code == 2 and error.count("\n") == 1, error
    assert error.startswith("marraztu record: error: argument --fps:") and "(see marraztu record --help)" in error
    assert not list(tmp_path.iterdir())


@pytest.mark.skipif(importlib.util.find_spec("imageio_ffmpeg") is not None, reason="imageio-ffmpeg is installed")
def test_mp4_without_imageio_ffmpeg_says_what_to_install(tmp_path: Path, capsys) -> None:
    assert main(["record", "-o", str(tmp_path / "turn.mp4"), "--size", SIZE, "--keys", "y"]) == 1
    assert "imageio-ffmpeg" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_f9_offscreen_says_where_recording_happens() -> None:
    import marraztu

    with marraztu.Viewer(size=(32, 32)) as viewer:
        assert "marraztu record" in viewer.press("F9").message


def test_f12_offscreen_says_where_the_picture_is(tmp_path: Path) -> None:
    """F12 saved nothing offscreen and said nothing: the key looked broken in --keys and in Python."""
    import marraztu

    with marraztu.Viewer(size=(32, 32)) as viewer:
        assert "F12 saves in the window" in viewer.press("F12").message
    assert not list(tmp_path.iterdir())
