"""The key map: one checked table from key token to command, shared by the window and `screenshot`.

A token is a character as typed (`f` and `F` differ, SPEC 6) or a named key: TAB, ENTER, ESC,
DELETE, F1, F9, F12, PAGEDOWN, PAGEUP, HOME. A key sequence on the command line is
whitespace-separated tokens; `TOKEN*N` repeats a press N times, `f=PATH` loads PATH (quote it as
`f="a b.obj"` when it holds spaces), and the mouse's words (MOUSE_WORDS) do what the window's mouse
does: `click=X,Y` clicks the pixel X columns and Y rows from the top-left, `drag=X1,Y1,X2,Y2` drags
from one pixel to another (`rdrag=` with the right button, `ctrl+drag=` with ctrl held) and `wheel=N`
turns the wheel N notches (negative: toward the person).
After `f`, until ENTER or ESC, tokens are typed into the file prompt as in the window: any single
character, SPACE and BACKSPACE (the drags and the wheel move the view meanwhile, as the window's do).
"""

from __future__ import annotations

import functools
import itertools
import re
import shlex
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from marraztu.control import commands
from marraztu.control.commands import CommandFunction, Host
from marraztu.errors import KeyMapError, shortened
from marraztu.model import viewports
from marraztu.model.lights import LIGHT_KEYS
from marraztu.model.scene import Scene

NAMED_KEYS = ("TAB", "ENTER", "ESC", "DELETE", "F1", "F9", "F12", "PAGEDOWN", "PAGEUP", "HOME")
_NAMED_ALIASES = {"ESCAPE": "ESC", "RETURN": "ENTER", "DEL": "DELETE", "PGDN": "PAGEDOWN", "PGUP": "PAGEUP"}
# Keys that only the file prompt reads, and what SPACE types there.
PROMPT_KEYS = ("BACKSPACE", "SPACE")
PROMPT_TEXT = {"SPACE": " "}
PROMPT_OPENER, PROMPT_CLOSERS = "f", ("ENTER", "ESC")
MAX_REPEAT = 100_000
MAX_SEQUENCE_PRESSES = 1_000_000
# shlex grows a word a character at a time, each step a copy: a sequence's text is bounded before it
# (a few dozen file paths of the longest a system allows; repeats say KEY*N).
MAX_SEQUENCE_CHARACTERS = 1 << 17
LOAD_PREFIX = "f="
CLICK_PREFIX, CLICK_TOKEN = "click=", "click"
# A left press and release with the pointer moved no further in all between them is a click, not a drag:
# a hand shakes a pixel or two (GTK's and Windows' drag thresholds are of this size).
CLICK_TRAVEL_PX = 3
MAX_WHEEL_NOTCHES = 100  # a word's notches are run one by one, as the window gets them


@dataclass(frozen=True)
class KeyPress:
    """One press: a key token, a load-this-file press (`token` "f" with `path` set) or a mouse word
    (`token` a name in MOUSE_WORDS with its `numbers` set: pixels from the top-left, or notches)."""

    token: str
    path: str | None = None
    numbers: tuple[int, ...] | None = None

    def __str__(self) -> str:
        if self.numbers is not None:
            return f"{self.token}={','.join(map(str, self.numbers))}"
        return self.token if self.path is None else f"{LOAD_PREFIX}{self.path}"

    @property
    def pixel(self) -> tuple[int, int] | None:
        """The pixel a mouse word presses its button on (None: no button is pressed on one)."""
        word = MOUSE_WORDS.get(self.token)
        if self.numbers is None or word is None or not word.pressed:
            return None
        return self.numbers[0], self.numbers[1]


def click(column: int, row: int) -> KeyPress:
    """The press of a left click on a pixel, column and row counted from the top-left."""
    return KeyPress(CLICK_TOKEN, numbers=(column, row))


MouseRun = Callable[[Scene, Host, tuple[int, ...]], None]


@dataclass(frozen=True)
class MouseWord:
    """A gesture of the mouse, written NAME=NUMBERS in --keys, and the control-layer function the window's
    handler of that gesture calls, with the same numbers."""

    name: str
    form: str  # its numbers, as a refusal shows them
    example: str
    pattern: re.Pattern[str]
    run: MouseRun
    pressed: bool  # its first two numbers are the pixel its button goes down on: in the picture
    refusal: Callable[[tuple[int, ...]], str | None] = lambda numbers: None  # numbers of its form it cannot take
    moves_past_prompt: bool = True  # the window's drags and wheel move the view while the `f` prompt is open
    presses: Callable[[tuple[int, ...]], int] = lambda numbers: 1  # what it counts toward MAX_SEQUENCE_PRESSES

    @property
    def prefix(self) -> str:
        return f"{self.name}="


_PIXEL = r"[0-9]{1,9}"
_PAIR = re.compile(rf"^{_PIXEL},{_PIXEL}$")
_TWO_PAIRS = re.compile(rf"^{_PIXEL},{_PIXEL},{_PIXEL},{_PIXEL}$")
_NOTCHES = re.compile(r"^-?[0-9]{1,9}$")


def _select(scene: Scene, host: Host, numbers: tuple[int, ...]) -> None:
    commands.select_at(scene, host, (numbers[0], numbers[1]))


def _dragging(name: str, move: commands.DragMove) -> MouseRun:
    """A drag from one pixel to the other as one motion (the button pressed, moved, released): one undo
    step, as a drag in the window is."""

    def run(scene: Scene, host: Host, numbers: tuple[int, ...]) -> None:
        refusal = mouse_refusal(KeyPress(name, numbers=numbers), host)
        if refusal is not None:
            scene.message = refusal
            return
        column, row, to_column, to_row = numbers
        commands.drag_by(scene, move, to_column - column, to_row - row, host.frame_size())
        commands.end_view_gesture(scene)  # the release

    return run


def _too_short(numbers: tuple[int, ...]) -> str | None:
    """A left drag the window would take as a click."""
    column, row, to_column, to_row = numbers
    if max(abs(to_column - column), abs(to_row - row)) > CLICK_TRAVEL_PX:
        return None
    return f"moves {CLICK_TRAVEL_PX} pixels or less, which the window takes as a click (click=X,Y)"


def _wheel(scene: Scene, host: Host, numbers: tuple[int, ...]) -> None:
    """The notches one by one, as the window gets them; one undo step, as a run of them in the window."""
    notches = numbers[0]
    for _ in range(abs(notches)):
        commands.dolly_view(scene, 1 if notches > 0 else -1)
    commands.end_view_gesture(scene)


def _notches_refusal(numbers: tuple[int, ...]) -> str | None:
    if 1 <= abs(numbers[0]) <= MAX_WHEEL_NOTCHES:
        return None
    return f"turns the wheel 1 to {MAX_WHEEL_NOTCHES} notches either way (wheel=N*K repeats it)"


def _any_drag(numbers: tuple[int, ...]) -> None:
    return None


def _drag_word(name: str, move: commands.DragMove,
               refusal: Callable[[tuple[int, ...]], str | None] = _any_drag) -> MouseWord:
    """A drag's word: NAME=X1,Y1,X2,Y2, its button pressed on the first pixel."""
    return MouseWord(name, "X1,Y1,X2,Y2", "300,300,400,300", _TWO_PAIRS, _dragging(name, move), pressed=True,
                     refusal=refusal)


def check_mouse_words(words: Iterable[MouseWord]) -> dict[str, MouseWord]:
    """The mouse's words as name -> word, refusing a name bound twice or one a key could be."""
    by_name: dict[str, MouseWord] = {}
    for word in words:
        if word.name in by_name or len(word.name) < 2 or word.name.upper() in NAMED_KEYS or "=" in word.name:
            raise KeyMapError(f"mouse words: {word.name!r} is bound twice or is no word's name")
        by_name[word.name] = word
    return by_name


# The window's drags move as far as the pointer went; the wheel dollies toward the selected object,
# wherever the pointer is (the window does not zoom toward it).
MOUSE_WORDS: dict[str, MouseWord] = check_mouse_words([
    MouseWord(CLICK_TOKEN, "X,Y", "400,300", _PAIR, _select, pressed=True, moves_past_prompt=False),
    _drag_word("drag", commands.DragMove.ORBIT, refusal=_too_short),
    _drag_word("rdrag", commands.DragMove.PAN),
    _drag_word("ctrl+drag", commands.DragMove.TURN_TARGET, refusal=_too_short),
    MouseWord("wheel", "N", "3", _NOTCHES, _wheel, pressed=False, refusal=_notches_refusal,
              presses=lambda numbers: abs(numbers[0])),  # each notch is a move of its own, as a key's press is
])
MOUSE_PREFIXES = tuple(word.prefix for word in MOUSE_WORDS.values())


@dataclass(frozen=True)
class Command:
    token: str
    description: str  # one short line for the help overlay
    run: CommandFunction
    state: Callable[[Scene], str] | None = None  # the switch's current value, for the help overlay
    # Keys listed on one line of the help, next to each other in the table (x y z, the lights): its words.
    together: str | None = None


# --- the table -------------------------------------------------------------------------------------
# ONE table for the six moving keys: token -> (axis index, sign).
AXIS_KEYS = {"x": (0, +1), "y": (1, +1), "z": (2, +1), "X": (0, -1), "Y": (1, -1), "Z": (2, -1)}
AXIS_WORDS = "rotate about / move along"


def _on_off(flag: bool) -> str:
    return "on" if flag else "off"


def _switch(token: str, description: str, switch: str, together: str | None = None) -> Command:
    """The key of one on/off switch of the modes, shown in the help overlay as on or off."""
    return Command(token, description, commands.toggle(switch), lambda scene: _on_off(getattr(scene.modes, switch)),
                   together)


def _light_state(key: str) -> Callable[[Scene], str]:
    def state(scene: Scene) -> str:
        light = commands.light_by_key(scene, key)
        return "none" if light is None else f"{light.name} {_on_off(light.on)}"

    return state


def _frame_state(scene: Scene) -> str:
    return f"objects {scene.modes.frame.value}, cameras {scene.modes.camera_mode.value}"


def _aperture_state(scene: Scene) -> str:
    light = scene.light
    return f"{light.name} {light.aperture_deg:g} deg" if light.aperture_deg < 180.0 else ""


def _axis_name(axis_index: int, sign: int) -> str:
    """An axis as the help says it: +x, -z."""
    return f"{'+' if sign > 0 else '-'}{'xyz'[axis_index]}"


def _axis_commands() -> list[Command]:
    of_sign = {sign: ", ".join(_axis_name(axis, way) for axis, way in AXIS_KEYS.values() if way == sign)
               for sign in (+1, -1)}  # one help line each: +x, +y, +z and -x, -y, -z
    return [Command(token, f"{AXIS_WORDS} {_axis_name(axis, sign)}", commands.axis_press(axis, sign),
                    _step_state if sign > 0 else None, together=f"{AXIS_WORDS} {of_sign[sign]}")
            for token, (axis, sign) in AXIS_KEYS.items()]


def _step_state(scene: Scene) -> str:
    """How far a press goes now (the translation follows what is targeted and its size): said once, on x y z's line."""
    return f"{commands.ROTATION_STEP_RAD:g} rad or {commands.translation_step(scene):g} units a press"


def _light_commands() -> list[Command]:
    return [Command(key, f"light {key} on/off", commands.light_switch(key), _light_state(key), "lights on / off")
            for key in LIGHT_KEYS]


def build_commands() -> list[Command]:
    """Every key of SPEC 6 and 8, in the order the help overlay lists them."""
    return [
        Command("f", "load a model file (f=PATH in --keys)", commands.request_file),
        Command("TAB", "select the next object / camera / light", commands.select_next),
        Command("ENTER", "select the next face of the object", commands.next_face,
                lambda s: "" if s.object is None else f"face {s.object.selected_face + 1}"),
        Command("c", "target objects / cameras / lights", commands.cycle_target,
                lambda s: s.modes.target.value),
        Command("r", "rotate from now on", commands.use_rotation, lambda s: s.modes.transform.value),
        Command("t", "translate from now on", commands.use_translation, lambda s: s.modes.transform.value),
        Command("g", "local / global; cameras: flight / analysis", commands.toggle_frame_or_camera_mode,
                _frame_state),
        *_axis_commands(),
        Command("u", "undo the last view move, else the target's last move", commands.undo),
        Command(".", "frame the selected object", commands.frame_selected,
                together="frame the selected object / everything shown"),
        Command(">", "frame everything shown", commands.frame_everything,
                together="frame the selected object / everything shown"),
        Command("HOME", "the view back to the start", commands.reset_view),
        Command("C", "look through the object / the camera", commands.toggle_view_from_object,
                lambda s: "object" if s.modes.view_from_object else "camera"),
        Command("l", "lines / filled", commands.toggle_fill, lambda s: s.modes.fill.value),
        Command("o", "whole objects / selected face only", commands.toggle("triangle_only"),
                lambda s: "face only" if s.modes.triangle_only else "whole"),
        Command("d", "all objects / selected only", commands.toggle("draw_all"),
                lambda s: "all" if s.modes.draw_all else "selected"),
        _switch("n", "normals on / off", "normals"),
        _switch("b", "back-face culling on / off", "culling"),
        Command("p", "perspective / parallel", commands.toggle_projection,
                lambda s: s.modes.projection.value),
        Command("F", "flat / Gouraud shading", commands.toggle_shading, lambda s: s.modes.shading.value),
        _switch("T", "texture on / off", "texture"),
        Command("v", "lit colour: all / ambient / diffuse / specular / each light / depth / normals",
                commands.cycle_term_view, Scene.term_view_name),
        Command("i", "lighting probe of the selected face", commands.toggle_probe,
                lambda s: _on_off(s.modes.probe)),
        _switch("m", "matrices panel", "matrices"),
        _switch("P", "pipeline: the selected face from model space to the window, clipping, culling", "pipeline"),
        _switch("s", "side by side: Flat | Gouraud | Phong", "side_by_side"),
        _switch("a", "grid and axes: the world's, and in local mode the object's own", "guides"),
        *_light_commands(),
        Command("+", "widen the spotlight", commands.change_aperture(+commands.APERTURE_STEP_DEG),
                _aperture_state, "widen / narrow the spotlight"),
        Command("-", "narrow the spotlight", commands.change_aperture(-commands.APERTURE_STEP_DEG),
                _aperture_state, "widen / narrow the spotlight"),
        Command("DELETE", "delete the selected object / camera", commands.delete_selected),
        Command("PAGEDOWN", "next model file in the selected one's folder, in its place", commands.step_file(+1)),
        Command("PAGEUP", "previous model file in that folder, in its place", commands.step_file(-1)),
        Command("F12", "save a screenshot", commands.save_screenshot),
        Command("F9", "record every new picture; F9 again saves them as a GIF", commands.toggle_recording),
        _switch("h", "help on / off", "show_help", together="help on / off"),
        _switch("F1", "help on / off", "show_help", together="help on / off"),
        Command("ESC", "quit", commands.quit_viewer),
    ]


def is_valid_token(token: str) -> bool:
    """A printable character as typed, or one of the named keys."""
    if token in NAMED_KEYS:
        return True
    return len(token) == 1 and token.isprintable() and not token.isspace()


def check_keymap(table: Iterable[Command]) -> dict[str, Command]:
    """The table as token -> command, refusing duplicate or impossible tokens, and keys listed together
    in the help that the table does not list next to each other."""
    by_token: dict[str, Command] = {}
    ended: set[str] = set()  # the help lines already closed
    previous: str | None = None
    for command in table:
        if not is_valid_token(command.token):
            raise KeyMapError(f"key table: {command.token!r} is not a key token")
        if command.token in by_token:
            raise KeyMapError(f"key table: {command.token!r} is bound twice")
        if command.together is not None and command.together in ended:
            raise KeyMapError(f"key table: {command.token!r} is listed with {command.together!r} but apart from it")
        if previous is not None and previous != command.together:
            ended.add(previous)
        previous = command.together
        by_token[command.token] = command
    return by_token


KEYMAP: dict[str, Command] = check_keymap(build_commands())


# --- presses ---------------------------------------------------------------------------------------
def normalise_token(token: str) -> str:
    """Named keys in any case and a few usual aliases ("Escape", "return"); characters as they are."""
    if len(token) <= 1:
        return token
    upper = token.upper()
    return _NAMED_ALIASES.get(upper, upper)


def _no_hint() -> str:
    return ""


def key_press(token: str, keymap: dict[str, Command] = KEYMAP, hint: Callable[[], str] = _no_hint) -> KeyPress:
    """The press of a token; KeyMapError names the token when no key has it, and adds what `hint` says
    (asked only then: most words are keys)."""
    name = normalise_token(token)
    if name not in keymap:
        mouse = ", ".join(f"{word.prefix}{word.form}" for word in MOUSE_WORDS.values())
        raise KeyMapError(f"unknown key {shortened(token)!r}{hint()}; keys are: {' '.join(keymap)}, f=PATH and "
                          f"{mouse}, separated by spaces (KEY*N presses one N times)")
    return KeyPress(name)


_REPEAT = re.compile(r"^(?P<token>.+)\*(?P<count>\d+)$")


def _miscounted(word: str, keymap: dict[str, Command]) -> bool:
    """A key's repeat of no whole count ('x*-1', 'x*1.5', 'x*'), which 'unknown key' would blame on the key."""
    key, star, _ = word.rpartition("*")
    return bool(star) and not word.startswith((LOAD_PREFIX, *MOUSE_PREFIXES)) and normalise_token(key) in keymap


def _parse_word(word: str, keymap: dict[str, Command], in_prompt: bool, opened_by: str | None = None,
                hint: Callable[[], str] = _no_hint) -> tuple[KeyPress, int]:
    """One word of a sequence: its press and how many times it repeats (`opened_by`: _prompt_press;
    `hint`: what an unknown key's refusal adds)."""
    count = 1
    match = _REPEAT.match(word)
    if match and not word.startswith(LOAD_PREFIX):  # a file name may hold "*2"; loads never repeat
        word, digits = match["token"], match["count"]
        count = int(digits) if len(digits) <= len(str(MAX_REPEAT)) else MAX_REPEAT + 1
        if not 1 <= count <= MAX_REPEAT:
            raise KeyMapError(f"{shortened(match.string)!r}: a repeat count must be 1 to {MAX_REPEAT}")
    elif not in_prompt and _miscounted(word, keymap):
        raise KeyMapError(f"{shortened(word)!r}: a repeat count must be 1 to {MAX_REPEAT}")
    if word.startswith(LOAD_PREFIX):
        path = word[len(LOAD_PREFIX):]
        if not path:
            raise KeyMapError("f= needs a file name: f=PATH")
        return KeyPress("f", path), count
    if word.startswith(MOUSE_PREFIXES):
        return _mouse_press(word), count
    if in_prompt:
        return _prompt_press(word, keymap, opened_by), count
    return key_press(word, keymap, hint), count


def _quoting_hint(words: list[str], at: int, keymap: dict[str, Command]) -> str:
    """For words[at] right after f=PATH: that path and the words up to the next key, quoted as one, as
    an unknown word there is most often the rest of a path its spaces split."""
    if at == 0 or not words[at - 1].startswith(LOAD_PREFIX):
        return ""
    following = (words[index] for index in range(at, len(words)))  # no copy of the rest for each f=PATH
    rest = itertools.takewhile(lambda word: not _names_a_key(word, keymap), following)
    path = " ".join([words[at - 1][len(LOAD_PREFIX):], *rest])
    return f" (a path with spaces is quoted inside the keys: {shortened(LOAD_PREFIX + shlex.quote(path))})"


def _names_a_key(word: str, keymap: dict[str, Command]) -> bool:
    return word.startswith((LOAD_PREFIX, *MOUSE_PREFIXES)) or normalise_token(word.partition("*")[0]) in keymap


def _mouse_press(word: str) -> KeyPress:
    """A mouse word: `click=X,Y`, `drag=X1,Y1,X2,Y2`..., pixels from the top-left (whether the picture
    holds them is known only when it is pressed)."""
    name, _, text = word.partition("=")
    mouse = MOUSE_WORDS[name]
    if mouse.pattern.match(text) is None:
        unit = "whole pixels from the top-left" if mouse.pressed else "notches, negative toward the person"
        raise KeyMapError(f"{shortened(word)!r}: a {name} is {mouse.prefix}{mouse.form}, {unit} "
                          f"({mouse.prefix}{mouse.example})")
    numbers = tuple(int(number) for number in text.split(","))
    refusal = mouse.refusal(numbers)
    if refusal is not None:
        raise KeyMapError(f"{shortened(word)!r}: {refusal}")
    return KeyPress(name, numbers=numbers)


def typed_into_prompt(key: KeyPress) -> bool:
    """Whether the open `f` prompt takes the press: every key, and a click (doing nothing), as in the window."""
    return key.numbers is None or not MOUSE_WORDS[key.token].moves_past_prompt


def mouse_refusal(key: KeyPress, host: Host) -> str | None:
    """Why a mouse word cannot be pressed now (None: it can): its button pressed off the picture."""
    if key.pixel is None:
        return None
    if key.token == CLICK_TOKEN:
        return commands.click_refusal(host, key.pixel)
    size = host.frame_size()
    if size is None:
        return "no picture to drag in"
    outside = viewports.pixel_refusal(key.pixel, size)
    return None if outside is None else f"{key}: its press at {outside}"


def _prompt_press(word: str, keymap: dict[str, Command], opened_by: str | None = None) -> KeyPress:
    """A press while the file prompt is open: any character, or a named key. `opened_by`: the earlier
    sequence that left the prompt open, which a refusal names (these keys opened none)."""
    if len(word) == 1 and word.isprintable():
        return KeyPress(word)
    name = normalise_token(word)
    if name in PROMPT_KEYS or name in keymap:
        return KeyPress(name)
    left_open = "" if opened_by is None else f" ({opened_by} left the file prompt open)"
    raise KeyMapError(f"{word!r} in the file prompt: type one character at a time (SPACE for a "
                      f"space, BACKSPACE), then ENTER{left_open}")


def parse_key_sequence(text: str, keymap: dict[str, Command] = KEYMAP, in_prompt: bool = False,
                       opened_by: str | None = None) -> list[KeyPress]:
    """'0 1 F x*10 f=model.obj' -> the presses, in order. KeyMapError on anything unknown. `in_prompt`:
    the `f` prompt is open before the first (an earlier sequence left it so), so they type into it; a
    word refused while that prompt is open names `opened_by`, the sequence that left it open."""
    if len(text) > MAX_SEQUENCE_CHARACTERS:
        raise KeyMapError(f"key sequence: more than {MAX_SEQUENCE_CHARACTERS} characters (KEY*N repeats a key)")
    try:
        words = shlex.split(text)
    except ValueError as error:  # an unclosed quote
        raise KeyMapError(f"key sequence {shortened(text)!r}: {error}") from error
    presses: list[KeyPress] = []
    counted = 0
    for at, word in enumerate(words):
        opened_by = opened_by if in_prompt else None  # a prompt these keys open is their own
        hint = functools.partial(_quoting_hint, words, at, keymap)
        press, count = _parse_word(word, keymap, in_prompt, opened_by, hint)
        counted += count * _presses_in(press)
        if counted > MAX_SEQUENCE_PRESSES:
            raise KeyMapError(f"key sequence: more than {MAX_SEQUENCE_PRESSES} presses (a wheel's notch counts as one)")
        presses.extend([press] * count)
        in_prompt = prompt_open_after([press], in_prompt)
    return presses


def _presses_in(press: KeyPress) -> int:
    """What one press counts toward MAX_SEQUENCE_PRESSES: a key 1, a wheel word its notches."""
    return 1 if press.numbers is None else MOUSE_WORDS[press.token].presses(press.numbers)


def prompt_open_after(presses: Iterable[KeyPress], in_prompt: bool = False) -> bool:
    """Whether the `f` prompt is open after `presses`, given whether it was before them."""
    for press in presses:
        if press.path is None:
            in_prompt = press.token not in PROMPT_CLOSERS if in_prompt else press.token == PROMPT_OPENER
    return in_prompt


def dispatch(scene: Scene, key: KeyPress, host: Host, keymap: dict[str, Command] = KEYMAP) -> None:
    """Runs one press. Never raises: a refused action or an unbound key leaves a message instead."""
    scene.message = ""  # the message answers the latest press; an older one would mislead
    commands.end_view_gesture(scene)
    if key.path is not None:
        commands.load_file(scene, host, key.path)
        return
    if key.numbers is not None:
        MOUSE_WORDS[key.token].run(scene, host, key.numbers)
        return
    command = keymap.get(key.token)
    if command is None:
        scene.message = f"key {key.token!r} does nothing (h: help)"
        return
    command.run(scene, host)
