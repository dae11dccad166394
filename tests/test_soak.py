"""Long sessions: tens of thousands of seeded random key presses through a real Viewer and Renderer
on EGL, with good and bad file loads, DELETEs and undo storms, checking the scene's invariants after
every press and GL state, pixels, live GL objects and memory as it goes.

The numbers (presses, GL objects, RSS) are printed; `pytest -s tests/test_soak.py` shows them.
"""

from __future__ import annotations

import random
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from marraztu.control.keymap import KEYMAP, KeyPress
from marraztu.loaders.images import fallback_texture
from marraztu.loaders.scenefile import empty_scene, load_builtin_scene
from marraztu.model.lights import SPOT_APERTURE_RANGE_DEG, TERM_VIEWS, TermView
from marraztu.model.scene import Scene, Target
from marraztu.render.gpu import MeshGpu, ObjectGpu
from marraztu.render.renderer import Renderer
from marraztu.resources import ASSET_DIR
from support import corpus
from support.scenes import RenderingViewer

PRESSES = 40_000
RENDER_EVERY = 50
SIZE = (64, 64)
MAX_ELEMENTS = 12  # objects + cameras: past this the soak presses DELETE, so frames stay cheap
RSS_GROWTH_LIMIT = 32 * corpus.MEGABYTE

# What a press is, beyond a uniformly drawn key of the map: loads of good and bad files (the same few
# again and again), deletions and storms of undo. Probabilities per press.
GOOD_LOAD, BAD_LOAD, DELETE, UNDO_STORM = 0.010, 0.006, 0.008, 0.003
UNDO_STORM_LENGTH = (30, 400)
SPECIAL_TOKENS = {"DELETE", "ESC"}  # DELETE has its own rate; ESC only asks the frontend to quit


class CountingFrontend:
    """The window's side of the host: counts what the keys asked of it."""

    def __init__(self) -> None:
        self.quits = self.screenshots = 0

    def quit(self) -> None:
        self.quits += 1

    def save_screenshot(self) -> None:
        self.screenshots += 1

    def notice(self, text: str) -> None: ...


@pytest.fixture(scope="module")
def soak_files(tmp_path_factory) -> tuple[list[str], list[str]]:
    """A few good models (one of the project's own) and a few bad files, loaded over and over."""
    folder = tmp_path_factory.mktemp("soak")
    good = [ASSET_DIR / "rammer.obj"]
    for name, content in (("triangle.obj", corpus.TRIANGLE + b"f 1 2 3\n"), ("seed.obj", corpus.VALID_OBJ)):
        (folder / name).write_bytes(content)
        good.append(folder / name)
    wanted = {"empty", "binary_noise", "index_past_end", "index_zero", "face_of_two_vertices",
              "nan_coordinate", "missing", "directory"}
    bad = [corpus.write_case(case, folder) for case in corpus.bad_obj_cases() if case.id in wanted]
    return [str(path) for path in good], [str(path) for path in bad]


@pytest.fixture
def soak_renderer(own_ctx) -> Iterator[Renderer]:
    yield from corpus.own_renderer(own_ctx)


# --------------------------------------------------------------------------------------------------
# Invariants
# --------------------------------------------------------------------------------------------------
@dataclass
class Invariants:
    """What must hold after every press; remembers each element's first matrix to compare with."""

    initial: dict[int, np.ndarray] = field(default_factory=dict)

    def after_press(self, scene: Scene) -> None:
        self._selection(scene)
        for obj in scene.objects + scene.cameras:
            assert obj.history, f"{obj.name}: empty history"
            if len(obj.history) == 1:  # a camera not yet moved takes a lone model's framing as its start
                self.initial[obj.uid] = obj.history[0].copy()
            assert np.array_equal(obj.history[0], self.initial[obj.uid]), f"{obj.name}: initial matrix changed"
            assert np.isfinite(obj.model).all(), f"{obj.name}: non-finite matrix"
            assert 0 <= obj.selected_face < max(obj.mesh.face_count, 1)
        for light in scene.lights:
            assert np.isfinite(light.position).all() and np.isfinite(light.direction).all()
            assert np.isfinite(light.axis_in_owner).all()
            if light.kind.has_cone:
                low, high = SPOT_APERTURE_RANGE_DEG
                assert low <= light.aperture_deg <= high

    @staticmethod
    def _selection(scene: Scene) -> None:
        assert scene.cameras, "the last camera is never deleted"
        assert 0 <= scene.selected_camera < len(scene.cameras)
        if scene.objects:
            assert 0 <= scene.selected_object < len(scene.objects)
        else:
            assert scene.selected_object == 0 and not scene.modes.view_from_object
        assert 0 <= scene.selected_light < len(scene.lights)

    @staticmethod
    def every_matrix(scene: Scene) -> None:
        """The whole of every history, not just the tops: slower, so only at checkpoints."""
        for obj in scene.objects + scene.cameras:
            assert np.isfinite(np.asarray(obj.history)).all(), f"{obj.name}: non-finite matrix in history"


# --------------------------------------------------------------------------------------------------
# The presses
# --------------------------------------------------------------------------------------------------
@dataclass
class PressMaker:
    """Seeded presses: first every key of the map once, then random ones at the rates above."""

    rng: random.Random
    good: list[str]
    bad: list[str]
    pending: list[KeyPress] = field(init=False)
    keys: list[str] = field(init=False)
    loads: int = 0
    bad_loads: int = 0
    prompts: int = 0  # presses made while the `f` prompt was open

    def __post_init__(self) -> None:
        self.keys = [token for token in KEYMAP if token not in SPECIAL_TOKENS]
        self.pending = [KeyPress(token) for token in reversed(list(KEYMAP))]

    def next(self, scene: Scene, prompt_open: bool) -> KeyPress:
        if prompt_open:  # type a little into the prompt, then load what was typed or cancel
            self.prompts += 1
            return KeyPress(self.rng.choice(["a", ".", "BACKSPACE", "SPACE", "ENTER", "ESC"]))
        if self.pending:
            return self.pending.pop()
        if len(scene.objects) + len(scene.cameras) > MAX_ELEMENTS and scene.modes.target is not Target.LIGHTS:
            return KeyPress("DELETE")
        roll = self.rng.random()
        if roll < GOOD_LOAD:
            self.loads += 1
            return KeyPress("f", self.rng.choice(self.good))
        roll -= GOOD_LOAD
        if roll < BAD_LOAD:
            self.bad_loads += 1
            return KeyPress("f", self.rng.choice(self.bad))
        roll -= BAD_LOAD
        if roll < DELETE:
            return KeyPress("DELETE")
        roll -= DELETE
        if roll < UNDO_STORM:
            self.pending = [KeyPress("u")] * self.rng.randint(*UNDO_STORM_LENGTH)
            return KeyPress("u")
        return KeyPress(self.rng.choice(self.keys))


@dataclass
class Checkpoint:
    press: int
    elements: int
    gl_objects: int
    rss: int


def gl_total(ctx) -> int:
    return sum(corpus.live_gl_objects(ctx).values())


def test_soak_random_keys_keep_the_scene_sound(own_ctx, soak_renderer: Renderer, soak_files) -> None:
    good, bad = soak_files
    scene = load_builtin_scene()
    frontend = CountingFrontend()
    viewer = RenderingViewer(scene, soak_renderer, frontend)
    scene.texture = fallback_texture()
    # The framebuffer first, and the depth view's programs (made when that view is first drawn), side by
    # side for every shading's.
    no_objects = empty_scene()
    no_objects.modes.term_view, no_objects.modes.side_by_side = TermView.DEPTH, True
    corpus.render_float(own_ctx, soak_renderer, no_objects, SIZE)
    gl_without_objects = gl_total(own_ctx)
    # Lines, both kinds of normals (of whole objects and of one face) and side by side, lit and in the
    # depth view, once, so every object holds all it ever will (the surface buffers at once; edges,
    # normal segments and a vertex array per surface program and lighting pass on first use), then back
    # to the start's modes.
    one_face_each = ["TAB"] * len(scene.objects)  # one face of the selected object only: each in turn
    to_depth_view = " ".join(["v"] * TERM_VIEWS.index(TermView.DEPTH))
    back_from_depth_view = " ".join(["v"] * (len(TERM_VIEWS) - TERM_VIEWS.index(TermView.DEPTH)))
    for keys in ("", "l n", "F", "o d", *one_face_each, "o d", "F n l", "s", to_depth_view, "s",
                 back_from_depth_view):
        viewer.press_sequence(keys)
        corpus.render_float(own_ctx, soak_renderer, scene, SIZE)
    per_object = (gl_total(own_ctx) - gl_without_objects) // len(scene.objects)
    assert per_object == MeshGpu.GL_OBJECTS + ObjectGpu.GL_OBJECTS  # the built-in scene's objects share no mesh
    assert gl_total(own_ctx) == gl_without_objects + per_object * len(scene.objects)

    maker = PressMaker(random.Random(corpus.SEED), good, bad)
    invariants = Invariants()
    checkpoints: list[Checkpoint] = []
    started = time.perf_counter()
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        for press_number in range(1, PRESSES + 1):
            press = maker.next(scene, viewer.prompt is not None)
            viewer.press(press)
            if press.path is not None and press.path in bad:
                assert Path(press.path).name in scene.message or scene.modes.target is Target.LIGHTS
            invariants.after_press(scene)
            if press_number % RENDER_EVERY == 0:
                invariants.every_matrix(scene)
                corpus.assert_sane_pixels(corpus.render_float(own_ctx, soak_renderer, scene, SIZE))
                if press_number % (RENDER_EVERY * 100) == 0:  # a census costs a garbage-collector walk
                    checkpoints.append(Checkpoint(press_number, len(scene.objects) + len(scene.cameras),
                                                  gl_total(own_ctx), corpus.current_rss_bytes()))
    seconds = time.perf_counter() - started

    assert dropped.leaked == 0, "GL objects dropped without release"
    for point in checkpoints:  # only what the scene's elements can account for is alive
        assert point.gl_objects <= gl_without_objects + per_object * point.elements, point
    third = len(checkpoints) // 3
    rss_growth = checkpoints[-1].rss - checkpoints[third].rss
    assert rss_growth < RSS_GROWTH_LIMIT, [point.rss for point in checkpoints]
    assert maker.loads > 100 and maker.bad_loads > 50
    assert frontend.quits and maker.prompts and frontend.screenshots  # ESC, f and F12 were pressed
    print(f"\nsoak: {PRESSES} presses in {seconds:.1f} s; {maker.loads} good and {maker.bad_loads} bad loads; "
          f"GL objects without models {gl_without_objects}, per model {per_object}; "
          f"checkpoints (press, elements, GL objects, RSS MB): "
          f"{[(p.press, p.elements, p.gl_objects, round(p.rss / corpus.MEGABYTE)) for p in checkpoints]}; "
          f"RSS growth over the last two thirds {rss_growth / corpus.MEGABYTE:.1f} MB")


def test_load_delete_loop_levels_off(own_ctx, soak_renderer: Renderer, soak_files) -> None:
    """A good load adds the same number of GL objects every time, a bad one none, DELETE gives them
    back; over hundreds of rounds neither GL objects nor resident memory creep up."""
    good, bad = soak_files
    scene = empty_scene()
    viewer = RenderingViewer(scene, soak_renderer, CountingFrontend())
    corpus.render_float(own_ctx, soak_renderer, scene, SIZE)
    baseline = gl_total(own_ctx)
    rounds, census_rounds = 300, {0, 1, 2, 3, 100, 200, 299}
    added: list[int] = []
    rss: dict[int, int] = {}
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        for round_number in range(rounds):
            census = round_number in census_rounds
            viewer.press(KeyPress("f", bad[round_number % len(bad)]))
            corpus.render_float(own_ctx, soak_renderer, scene, SIZE)
            if census:
                assert gl_total(own_ctx) == baseline, "a failed load left GL objects behind"
            viewer.press(KeyPress("f", good[round_number % len(good)]))
            assert len(scene.objects) == 1
            corpus.assert_sane_pixels(corpus.render_float(own_ctx, soak_renderer, scene, SIZE))
            if census:
                added.append(gl_total(own_ctx) - baseline)
            viewer.press(KeyPress("DELETE"))
            assert not scene.objects
            corpus.render_float(own_ctx, soak_renderer, scene, SIZE)
            if census:
                assert gl_total(own_ctx) == baseline, "DELETE did not give the GL objects back"
            if round_number in (50, rounds - 1):
                rss[round_number] = corpus.current_rss_bytes()
    assert dropped.leaked == 0
    assert len(set(added)) == 1 and added[0] > 0, added
    growth = rss[rounds - 1] - rss[50]
    assert growth < 16 * corpus.MEGABYTE, f"RSS grew {growth / corpus.MEGABYTE:.1f} MB over {rounds - 51} rounds"
    print(f"\nload/delete loop: {rounds} rounds, each good load +{added[0]} GL objects, bad load +0, DELETE "
          f"back to {baseline}; RSS {rss[50] / corpus.MEGABYTE:.1f} -> {rss[rounds - 1] / corpus.MEGABYTE:.1f} MB")


def test_every_key_of_the_map_is_pressed_by_the_soak(soak_files) -> None:
    """The soak's first presses are the whole key map, so no key can be left out by chance."""
    maker = PressMaker(random.Random(corpus.SEED), *soak_files)
    scene = empty_scene()
    first = [maker.next(scene, prompt_open=False).token for _ in range(len(KEYMAP))]
    assert sorted(first) == sorted(KEYMAP)


def test_the_gl_object_counters_see_a_leak(own_ctx) -> None:
    """The counters above are not vacuous: a buffer held is counted live, one dropped unreleased is
    counted dropped, and a released one is neither."""
    corpus.make_current(own_ctx)
    before = gl_total(own_ctx)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        held = own_ctx.buffer(reserve=64)
        assert gl_total(own_ctx) == before + 1
        own_ctx.buffer(reserve=64)  # dropped at once, never released: a leak
        released = own_ctx.buffer(reserve=64)
        released.release()
        del released
        assert dropped.count() == 1
    assert dropped.leaked == 1
    held.release()
    assert gl_total(own_ctx) == before
