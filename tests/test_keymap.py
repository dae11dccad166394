"""The key table, key sequences and dispatch: no GL."""

from __future__ import annotations

import numpy as np
import pytest

from marraztu.control import keymap
from marraztu.control.keymap import (
    AXIS_KEYS,
    KEYMAP,
    Command,
    KeyPress,
    build_commands,
    check_keymap,
    dispatch,
    parse_key_sequence,
)
from marraztu.errors import KeyMapError
from marraztu.model.mesh import Mesh
from marraztu.model.scene import Material, Scene, SceneObject, Target
from support.scenes import RecordingHost

SPEC_KEYS = set("f l o d r t g x y z X Y Z u c C n b p F + - 0 1 2 3".split()) | {"TAB", "ENTER", "ESC"}
PROJECT_KEYS = {"T", "h", "F1", "F9", "F12", "P", "DELETE", "v", "i", "m", "s", "PAGEDOWN", "PAGEUP", "a", ".", ">",
                "HOME"}


def triangle_scene() -> Scene:
    """One triangle object and one triangle camera: the least a scene needs."""
    mesh = Mesh(
        name="tri",
        positions=np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        corner_vertex=np.arange(3, dtype=np.int64),
        uvs=np.zeros((3, 2), np.float32),
        normals=np.tile(np.float32([0, 0, 1]), (3, 1)),
        face_start=np.array([0, 3], dtype=np.int64),
        face_normals=np.float32([[0, 0, 1]]),
    )
    material = Material((0.1, 0.1, 0.1), (0.5, 0.5, 0.5), (0.2, 0.2, 0.2), 20.0)
    return Scene(objects=[SceneObject.placed("tri", mesh, material, (0, 0, 0))],
                 cameras=[SceneObject.placed("cam", mesh, material, (0, 0, 150))])


# --- the table -------------------------------------------------------------------------------------
def test_every_key_of_the_spec_and_the_project_is_bound() -> None:
    assert SPEC_KEYS | PROJECT_KEYS == set(KEYMAP)


def test_the_six_moving_keys_come_from_one_table() -> None:
    assert AXIS_KEYS == {"x": (0, 1), "y": (1, 1), "z": (2, 1), "X": (0, -1), "Y": (1, -1), "Z": (2, -1)}


def test_every_command_has_a_description() -> None:
    assert all(command.description for command in KEYMAP.values())


def test_check_catches_a_duplicate_token() -> None:
    table = build_commands() + [Command("x", "again", lambda scene, host: None)]
    with pytest.raises(KeyMapError, match="'x' is bound twice"):
        check_keymap(table)


def test_check_catches_keys_listed_together_but_apart_in_the_table() -> None:
    table = build_commands()
    h = next(command for command in table if command.token == "h")
    table.remove(h)
    table.insert(0, h)  # h and F1 share a help line: apart, the help would say it twice
    with pytest.raises(KeyMapError, match="'F1' is listed with 'help on / off' but apart from it"):
        check_keymap(table)


@pytest.mark.parametrize("token", ["", "ab", " ", "\t", "SPACEBAR", "f1"])
def test_check_catches_an_impossible_token(token: str) -> None:
    with pytest.raises(KeyMapError, match="not a key token"):
        check_keymap([Command(token, "bad", lambda scene, host: None)])


# --- key sequences ---------------------------------------------------------------------------------
@pytest.mark.parametrize(("text", "tokens"), [
    ("", []),
    ("x", ["x"]),
    ("  0 1\tF \n", ["0", "1", "F"]),
    ("x*3 Y", ["x", "x", "x", "Y"]),
    ("TAB ENTER ESC DELETE F1 F12", ["TAB", "ENTER", "ESC", "DELETE", "F1", "F12"]),
    ("tab Enter escape Return del f12", ["TAB", "ENTER", "ESC", "ENTER", "DELETE", "F12"]),
    ("+ - +*2", ["+", "-", "+", "+"]),
    ("f F", ["f", "F"]),
])
def test_parse_key_sequence(text: str, tokens: list[str]) -> None:
    assert [press.token for press in parse_key_sequence(text)] == tokens


def test_parse_load_presses() -> None:
    presses = parse_key_sequence('c f=models/a.obj f="with space/b.obj" f=\'q.obj\'')
    assert presses == [KeyPress("c"), KeyPress("f", "models/a.obj"), KeyPress("f", "with space/b.obj"),
                       KeyPress("f", "q.obj")]
    assert str(presses[1]) == "f=models/a.obj"


@pytest.mark.parametrize(("text", "named"), [
    ("0 q 1", "'q'"),
    ("xx", "'xx'"),
    ("x*0", "x\\*0"),
    (f"x*{keymap.MAX_REPEAT + 1}", "repeat count"),
    ("x*-1", "'x\\*-1'"),
    ("f=", "f=PATH"),
    ('f="unclosed', "closing quotation"),
    ("SPACE", "'SPACE'"),
])
def test_parse_errors_name_the_bad_token(text: str, named: str) -> None:
    with pytest.raises(KeyMapError, match=named):
        parse_key_sequence(text)


@pytest.mark.parametrize("text", ["x5", "xx"])
def test_an_unknown_key_says_how_keys_are_written(text: str) -> None:
    """A lesson's press("x5") was told every key but not that x*5 presses x five times."""
    with pytest.raises(KeyMapError, match=r", separated by spaces \(KEY\*N presses one N times\)$"):
        parse_key_sequence(text)


@pytest.mark.parametrize(("text", "unknown", "quoted"), [
    ("f=my models/pato.glb", "models/pato.glb", "f='my models/pato.glb'"),
    ("y f=my big models/pato.glb y", "big", "f='my big models/pato.glb'"),
])
def test_an_unknown_word_after_a_load_says_how_a_path_with_spaces_is_written(text: str, unknown: str,
                                                                               quoted: str) -> None:
    """--keys "f=my models/pato.glb" said only "unknown key 'models/pato.glb'" and every key."""
    with pytest.raises(KeyMapError) as refused:
        parse_key_sequence(text)
    assert str(refused.value).startswith(
        f"unknown key {unknown!r} (a path with spaces is quoted inside the keys: {quoted}); keys are: ")
    assert [press.path for press in parse_key_sequence(quoted)] == [quoted[3:-1]]


def test_the_quoting_hint_is_worked_out_only_for_a_refused_word(monkeypatch: pytest.MonkeyPatch) -> None:
    """It was worked out for every word after a load, refused or not, and inside the file prompt, which never
    says it: a third more time to read 'f=a.obj y' 8000 times."""
    from marraztu.control import keymap

    hints: list[int] = []
    quoting_hint = keymap._quoting_hint
    monkeypatch.setattr(keymap, "_quoting_hint",
                        lambda words, at, keys: hints.append(at) or quoting_hint(words, at, keys))
    assert len(parse_key_sequence("f=a.obj y " * 3 + "f a SPACE b ENTER")) == 11
    assert hints == []
    with pytest.raises(KeyMapError, match=r"^unknown key 'b\.obj' \(a path with spaces is quoted inside the keys: "):
        parse_key_sequence("y f=a b.obj")
    assert hints == [2]


def test_an_unknown_word_after_a_key_has_no_quoting_hint() -> None:
    with pytest.raises(KeyMapError) as refused:
        parse_key_sequence("f=a.obj y models")
    assert "quoted" not in str(refused.value)


def test_parse_bounds_the_whole_sequence() -> None:
    with pytest.raises(KeyMapError, match="presses"):
        parse_key_sequence(" ".join(["x*100000"] * 11))


def test_parse_bounds_the_text_before_splitting_it() -> None:
    """shlex grows a word a character at a time: a word of megabytes would cost its length squared."""
    longest = keymap.MAX_SEQUENCE_CHARACTERS
    assert parse_key_sequence("f=" + "a" * (longest - 2)) == [KeyPress("f", "a" * (longest - 2))]
    with pytest.raises(KeyMapError, match="characters"):
        parse_key_sequence("f=" + "a" * (1 << 24))


# --- dispatch --------------------------------------------------------------------------------------
@pytest.mark.parametrize("target", list(Target))
@pytest.mark.parametrize("token", sorted(KEYMAP))
def test_no_valid_key_raises_under_any_target(token: str, target: Target) -> None:
    scene = triangle_scene()
    scene.modes.target = target
    dispatch(scene, KeyPress(token), RecordingHost())
    dispatch(scene, KeyPress(token), RecordingHost())


def test_every_key_twice_in_a_row_under_every_mode_never_raises() -> None:
    scene = triangle_scene()
    host = RecordingHost()
    for _ in range(3):
        for token in KEYMAP:
            for _ in range(2):
                dispatch(scene, KeyPress(token), host)
    assert len(scene.cameras) == 1


def test_an_unbound_key_leaves_a_message() -> None:
    scene = triangle_scene()
    dispatch(scene, KeyPress("q"), RecordingHost())
    assert "'q'" in scene.message


def test_a_press_clears_the_previous_message() -> None:
    scene = triangle_scene()
    scene.message = "old news"
    dispatch(scene, KeyPress("l"), RecordingHost())
    assert scene.message == ""


@pytest.mark.parametrize("word", ["x*-1", "x*1.5", "x*", "TAB*two", "pagedown*-3"])
def test_a_known_key_of_no_whole_count_is_blamed_on_the_count(word: str) -> None:
    """'x*-1' said 'unknown key', though x is one: the count is what is wrong."""
    with pytest.raises(KeyMapError, match="a repeat count must be 1 to"):
        parse_key_sequence(word)


@pytest.mark.parametrize("count", ["9" * 5000, "0" * 5000 + "1", "1" + "0" * 30])
def test_a_repeat_count_of_any_length_is_one_error(count: str) -> None:
    with pytest.raises(KeyMapError, match="repeat count") as caught:
        parse_key_sequence(f"x*{count}")
    assert len(str(caught.value)) < 200
