"""The view as people expect to handle it: a lone model framed whatever its units, `.` to frame the
selected object, HOME back to the start, a camera loaded with `f` standing outside the scene, and the
mouse's orbit, pan and dolly, each gesture one step for `u`."""

from __future__ import annotations

import gc
import math
import warnings
import weakref
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import marraztu
from marraztu.control import commands
from marraztu.control.keymap import dispatch, parse_key_sequence
from marraztu.control.viewer import DARK_HINT, StartOptions, Viewer, load_model_object
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.registry import load_model
from marraztu.loaders.scenefile import DEFAULT_MATERIAL, empty_scene, load_builtin_scene
from marraztu.model.build import build_mesh
from marraztu.model.framing import FILL, bounding_sphere
from marraztu.model.scene import HALF_HEIGHT_RANGE, Scene, SceneObject, Sight, world_boxes
from marraztu.model.transforms import placement
from support.scenes import BACKGROUND, NoFrontend, RecordingHost

SIZE = (160, 160)


def octahedron(path: Path, size: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Path:
    """A round-ish model of radius `size`, its six tips on the axes through `centre`."""
    tips = [(size, 0, 0), (-size, 0, 0), (0, size, 0), (0, -size, 0), (0, 0, size), (0, 0, -size)]
    tips = [tuple(float(np.float64(at) + offset) for at, offset in zip(tip, centre)) for tip in tips]
    faces = [(1, 3, 5), (3, 2, 5), (2, 4, 5), (4, 1, 5), (3, 1, 6), (2, 3, 6), (4, 2, 6), (1, 4, 6)]
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in tips)
                    + "".join(f"f {a} {b} {c}\n" for a, b, c in faces))
    return path


def picture(tmp_path: Path, keys: str = "", models: tuple[Path, ...] = (), empty: bool = True,
            name: str = "shot.png", size: tuple[int, int] = SIZE) -> np.ndarray:
    out = take_screenshot(StartOptions(empty=empty, models=models), tmp_path / name, size, keys=keys)
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


def covered_rows(pixels: np.ndarray) -> int:
    rows = np.flatnonzero((pixels != BACKGROUND).any(axis=2).any(axis=1))
    return int(rows[-1] - rows[0] + 1) if rows.size else 0


def viewer_with(keys: str, models: tuple[Path, ...] = (), empty: bool = False) -> Viewer:
    viewer = Viewer(empty_scene() if empty else load_builtin_scene(), NoFrontend())
    viewer.start(StartOptions(empty=empty, models=models), longest_texture_side=64)
    for key in parse_key_sequence(keys):
        viewer.press(key)
    return viewer


# --- framing -------------------------------------------------------------------------------------
# In perspective the bounding sphere's outline fills FILL of the view's height; the octahedron's tips,
# on the sphere but level with its centre, span sin(atan(FILL)) of it (90 degree field: tan 45 = 1).
# `p` keeps that size (SPEC 5's matching depth); `.` in parallel projection makes the sphere FILL.
@pytest.mark.parametrize("size", [1e-10, 1e-3, 1.0, 1e4])  # 1e-10: a molecule in metres
@pytest.mark.parametrize(("keys", "share"), [("", math.sin(math.atan(FILL))), ("p", math.sin(math.atan(FILL))),
                                             ("p .", FILL)])
def test_a_lone_model_is_framed_whatever_its_units(tmp_path: Path, size: float, keys: str, share: float) -> None:
    pixels = picture(tmp_path, keys, (octahedron(tmp_path / "m.obj", size),))
    assert covered_rows(pixels) == pytest.approx(share * SIZE[1], abs=3)
    assert tuple(pixels[SIZE[1] // 2, SIZE[0] // 2]) != BACKGROUND  # centred


def covered_columns(pixels: np.ndarray) -> int:
    return covered_rows(pixels.transpose(1, 0, 2))


@pytest.mark.parametrize(("keys", "size"), [("s .", (480, 320)), ("s p .", (480, 320)), ("", (80, 160)),
                                            ("p .", (80, 160))])
def test_a_view_narrower_than_high_is_framed_by_its_width(tmp_path: Path, keys: str, size: tuple[int, int]) -> None:
    """Side by side, each third of an 800x800 window is 266 wide: `.` framed by the height alone, so a
    round model ran off both sides of every third. A lone model at start in a tall window did too."""
    pixels = picture(tmp_path, keys, (octahedron(tmp_path / "m.obj", 2.0),), size=size)
    width = size[0] // 3 if keys.startswith("s") else size[0]
    third = pixels[:, width + 2:2 * width - 2] if keys.startswith("s") else pixels  # within the separators
    aspect = width / size[1]  # tan(half width) in a 90 degree high view
    share = FILL if "p" in keys else math.sin(math.atan(FILL * aspect)) / aspect  # the tips, level with the centre
    assert covered_columns(third) == pytest.approx(share * width, abs=3)
    assert (third[:, [0, -1]] == BACKGROUND).all()  # clear of the sides


def test_the_framed_start_is_the_same_at_every_scale(tmp_path: Path) -> None:
    small = picture(tmp_path, "", (octahedron(tmp_path / "a.obj", 1e-3),), name="a.png")
    large = picture(tmp_path, "", (octahedron(tmp_path / "b.obj", 1e4),), name="b.png")
    tiny = picture(tmp_path, "", (octahedron(tmp_path / "c.obj", 1e-10),), name="c.png")
    assert (np.abs(small - large).max(axis=2) > 2).mean() < 0.01
    assert (np.abs(small - tiny).max(axis=2) > 2).mean() < 0.01


def test_the_built_in_scene_is_not_reframed_by_a_model_added_to_it(tmp_path: Path) -> None:
    viewer = viewer_with("", (octahedron(tmp_path / "m.obj", 1e4),))
    assert np.array_equal(viewer.scene.camera.model, load_builtin_scene().camera.model)
    flat = viewer_with("", (box(tmp_path / "ground.obj", (20.0, 0.0, 20.0)),))
    assert np.array_equal(flat.scene.camera.model, load_builtin_scene().camera.model)


BOX_FACES = [(1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2), (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4)]  # outward


def box(path: Path, extents: tuple[float, float, float], centre: tuple[float, float, float] = (0.0, 0.0, 0.0),
        inward: bool = False) -> Path:
    """A box of these extents about `centre`, its faces outward (a flat one is a plate) or inward (a room)."""
    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)] * np.array(extents) / 2.0 + centre
    faces = [face[::-1] if inward else face for face in BOX_FACES]
    path.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in corners)
                    + "".join("f " + " ".join(map(str, face)) + "\n" for face in faces))
    return path


@pytest.mark.parametrize("extents", [(20.0, 0.0, 20.0), (0.4, 0.4, 100.0), (50.0, 3.0, 50.0)],
                         ids=["a ground plane", "a beam along the view", "a flat building"])
def test_a_lone_model_seen_edge_or_end_on_is_shown_from_above_right_and_in_front(
        tmp_path: Path, extents: tuple[float, float, float]) -> None:
    """The start camera looks along -z: such a model showed an empty picture or a dot."""
    viewer = viewer_with("", (box(tmp_path / "m.obj", extents),), empty=True)
    assert np.allclose(viewer.scene.camera.forward, -np.ones(3) / np.sqrt(3.0))
    assert np.allclose(viewer.scene.camera.model[:3, 1] @ [0.0, 1.0, 0.0], np.sqrt(2.0 / 3.0))  # y stays up
    pixels = picture(tmp_path, "", (tmp_path / "m.obj",))
    assert (pixels != BACKGROUND).any(axis=2).mean() > 0.001  # the beam a thin line, where end on a dot
    standing = viewer_with("", (box(tmp_path / "s.obj", (20.0, 20.0, 0.0)),), empty=True)
    assert np.allclose(standing.scene.camera.forward, [0.0, 0.0, -1.0])  # seen face on: as it was


def test_dot_frames_the_selected_object_and_u_takes_it_back(tmp_path: Path) -> None:
    model = (octahedron(tmp_path / "m.obj", 20.0),)
    start = picture(tmp_path, "", model, name="start.png")
    away = picture(tmp_path, "c t z*30 x*2 c c", model, name="away.png")
    framed = picture(tmp_path, "c t z*30 c c .", model, name="framed.png")
    undone = picture(tmp_path, "c t z*30 x*2 c c . u", model, name="undone.png")
    assert np.array_equal(framed, start)  # back along the same view axis: the start's very picture
    assert np.array_equal(undone, away) and not np.array_equal(away, start)


@pytest.mark.parametrize("keys", ["d .", "r z*8 d .", "c r Z*8 c c d ."],
                         ids=["level", "the plate turned", "the camera rolled"])
def test_dot_on_a_plate_seen_edge_on_looks_at_it_from_above(tmp_path: Path, keys: str) -> None:
    """A plate beside the ships seen edge on: `.` drew nothing. Turned about z its world box is not
    flat, and turned 0.8 rad (or the camera rolled back as far) the view from above, right and in
    front sees it edge on too: then from above, left and in front."""
    plate = box(tmp_path / "plate.obj", (20.0, 0.0, 20.0))
    assert not (picture(tmp_path, keys.replace(".", ""), (plate,), empty=False, name="before.png")
                != BACKGROUND).any()
    pixels = picture(tmp_path, keys, (plate,), empty=False)
    assert (pixels != BACKGROUND).any(axis=2).mean() > 0.1
    camera = viewer_with(keys, (plate,)).scene.camera
    assert camera.forward[1] < -0.5  # looking down on it


@pytest.mark.parametrize("centre,outside", [((0.0, 60.0, 0.0), False), ((0.0, 0.0, 400.0), True),
                                            ((3000.0, 0.0, 0.0), True)], ids=["above", "behind", "aside"])
def test_a_model_loaded_outside_the_view_says_so_and_dot_frames_it(
        tmp_path: Path, centre: tuple[float, float, float], outside: bool) -> None:
    viewer = viewer_with("", (octahedron(tmp_path / "m.obj", 1.0, centre),))
    assert ("outside the view (. frames it)" in viewer.scene.message) == outside
    assert (viewer.scene.sight(viewer.scene.object, 1.0) is Sight.OUTSIDE) == outside
    viewer.press(parse_key_sequence(".")[0])
    assert viewer.scene.sight(viewer.scene.object, 1.0) is not Sight.OUTSIDE


@pytest.mark.parametrize("size,small", [(0.01, True), (1e-4, True), (1.0, False)])
def test_a_model_loaded_too_small_to_see_says_so_and_dot_frames_it(tmp_path: Path, size: float,
                                                                    small: bool) -> None:
    """A model in millimetres loaded among the ships, 150 units off, drew nothing without a word."""
    viewer = viewer_with("", (octahedron(tmp_path / "m.obj", size, (0.0, 60.0, 0.0)),))
    assert ("too small to see from here (. frames it)" in viewer.scene.message) == small, viewer.scene.message
    assert (viewer.scene.sight(viewer.scene.object, 1.0) is Sight.TOO_SMALL) == small
    viewer.press(parse_key_sequence(".")[0])
    assert viewer.scene.sight(viewer.scene.object, 1.0) is not Sight.TOO_SMALL


AROUND_WORDS = ", around the camera (. frames it from outside)"


@pytest.mark.parametrize(("model", "keys", "around"), [
    (("sheet.obj", (1e6, 1.0, 1e6), (0.0, 0.0, 0.0)), "", True),
    (("room.obj", (20.0, 20.0, 20.0), (0.0, 0.0, 150.0)), "", True),
    (("room.obj", (20.0, 20.0, 20.0), (0.0, 0.0, 150.0)), "f=", True),
    (("room.obj", (20.0, 20.0, 20.0), (0.0, 0.0, 100.0)), "f=", False),
], ids=["a sheet on the command line", "a room on the command line", "a room with f", "a room ahead"])
def test_a_model_loaded_around_the_camera_says_so_and_dot_frames_it_from_outside(
        tmp_path: Path, model: tuple[str, tuple[float, float, float], tuple[float, float, float]], keys: str,
        around: bool) -> None:
    """A sheet 1e6 across or a room 20 across loaded round the built-in scene's camera (0 0 150) showed
    its inside, back faces in red, with no word of why."""
    name, extents, centre = model
    path = box(tmp_path / name, extents, centre, inward=name == "room.obj")
    viewer = viewer_with(f"f={path}" if keys else "", () if keys else (path,))
    assert f"loaded {name} as a new object" in viewer.scene.message and (AROUND_WORDS in viewer.scene.message) == around
    assert viewer.scene.around_eye([viewer.scene.object]) == [around]
    viewer.press(parse_key_sequence(".")[0])
    assert viewer.scene.around_eye([viewer.scene.object]) == [False] and AROUND_WORDS not in viewer.scene.message


def test_a_turned_model_is_around_the_camera_only_where_its_own_box_holds_the_eye(tmp_path: Path) -> None:
    """A long beam turned 45 degrees about y: its world box holds a point beside it that its own box does not."""
    viewer = viewer_with("", (box(tmp_path / "beam.obj", (100.0, 1.0, 1.0)),), empty=True)
    scene = viewer.scene
    turn = np.eye(4)
    turn[[0, 0, 2, 2], [0, 2, 0, 2]] = np.array([1.0, 1.0, -1.0, 1.0]) / np.sqrt(2.0)
    scene.object.model = turn
    camera = scene.camera.model.copy()
    for at, around in (((10.0, 0.0, 10.0), False), ((10.0, 0.0, -10.0), True)):
        camera[:3, 3] = at
        scene.camera.model = camera.copy()
        assert scene.around_eye([scene.object]) == [around]


THIN_WORDS = "thinner than a pixel from here (l draws its edges)"


def test_a_beam_framed_under_a_pixel_thick_says_so_and_l_draws_it(tmp_path: Path) -> None:
    """A 1000:1 beam framed whole in a view 300 pixels high is 0.2 of a pixel thick: the picture was
    empty and the messages said nothing of why."""
    beam = box(tmp_path / "beam.obj", (1000.0, 1.0, 1.0), (500.0, 0.5, 0.5))
    empty = picture(tmp_path, "", (beam,), name="filled.png", size=(400, 300))
    assert not (empty != BACKGROUND).any()  # the rasteriser lights no pixel centre: the picture stays as it was
    assert (picture(tmp_path, "l", (beam,), name="lines.png", size=(400, 300)) != BACKGROUND).any(axis=2).sum() > 100
    with marraztu.Viewer(size=(400, 300), empty=True) as viewer:
        viewer.load(beam)
        assert viewer.message.endswith(f"6 faces, {THIN_WORDS}"), viewer.message
        viewer.press(".")
        assert viewer.message == f"framed beam, {THIN_WORDS}"
        viewer.press("l .")
        assert viewer.message == "framed beam"  # lines light pixels however thin
        viewer.size = (4000, 3000)
        viewer.press("l .")
        assert viewer.message == "framed beam"  # 2 pixels thick
    at_start = Viewer(empty_scene(), NoFrontend(), frame_size=lambda: (400, 300))
    at_start.start(StartOptions(empty=True, models=(beam,)), longest_texture_side=64)
    assert at_start.scene.message.splitlines()[-1] == f"beam: {THIN_WORDS}"
    assert "thinner" not in viewer_with("", (beam,), empty=True).scene.message  # no picture drawn: none too thin
    with marraztu.Viewer(size=(400, 300)) as viewer:  # beside the ships
        viewer.load(beam)
        viewer.press(".")
        assert viewer.message == f"framed beam, {THIN_WORDS}"


def test_a_model_under_a_pixel_every_way_is_said_too_small_not_thin(tmp_path: Path) -> None:
    """A speck 0.4 pixels across, 150 units off in a view 300 pixels high, spans more than SEEN_SHARE_LEAST
    of it: said thinner than a pixel, with l for a cure, where `.` is the one."""
    speck = octahedron(tmp_path / "speck.obj", 0.2, (0.0, 60.0, 0.0))
    for size, said in (((400, 300), ", too small to see from here (. frames it)"), ((4000, 3000), "")):
        with marraztu.Viewer(size=size) as viewer:  # 4 pixels across in the larger
            viewer.load(speck)
            assert viewer.message.endswith(f"8 faces{said}"), viewer.message


@pytest.mark.parametrize("extents,thin", [((1.0, 1.0, 1000.0), True), ((1e6, 1.0, 1e6), False),
                                          ((1e6, 1e6, 1.0), False), ((10.0, 1.0, 1.0), False)],
                         ids=["a needle along the view", "a sheet", "a sheet facing the view", "a 10:1 beam"])
def test_only_a_model_under_a_pixel_across_is_said_thin(tmp_path: Path, extents: tuple[float, float, float],
                                                        thin: bool) -> None:
    model = box(tmp_path / "m.obj", extents)
    for empty in (True, False):
        with marraztu.Viewer(size=(400, 300), empty=empty) as viewer:
            viewer.load(model)
            viewer.press(".")
            assert (viewer.message == f"framed m, {THIN_WORDS}") == thin, viewer.message
            assert viewer.message.startswith("framed m")


@pytest.mark.parametrize("centre,size,inside", [((0.0, 0.0, 0.0), 1.0, True), ((0.0, 60.0, 0.0), 1.0, False),
                                                ((0.0, 0.0, 0.0), 1e-4, True)],
                         ids=["at the origin", "above", "too small to see, at the origin"])
def test_a_model_loaded_inside_another_says_so(tmp_path: Path, centre: tuple[float, float, float], size: float,
                                               inside: bool) -> None:
    """A student's 2-unit model added to the built-in scene lands at the origin inside Rammer_255 and
    was drawn hidden there, the load's message saying nothing of it; a 0.2 mm one was said too small
    to see, and `.` showed it against Rammer_255's inside, drawn red, without a word of why."""
    model = octahedron(tmp_path / "m.obj", size, centre)
    hidden = "inside Rammer_255's bounding box, perhaps hidden by it (d shows it alone)"
    assert (hidden in viewer_with("", (model,)).scene.message) == inside
    with marraztu.Viewer(size=SIZE) as v:
        assert hidden not in v.press("d").load(model).message  # d: the others are not drawn


def test_a_command_line_model_inside_anothers_box_says_so_as_a_loaded_one_does(tmp_path: Path) -> None:
    """Two models on the command line, framed together, the small one inside the big one's box: the
    start said nothing of it, where the same file loaded with `f` said it may be hidden there."""
    big, small = octahedron(tmp_path / "big.obj", 100.0), octahedron(tmp_path / "small.obj", 10.0)
    hidden = "inside big's bounding box, perhaps hidden by it (d shows it alone)"
    assert hidden in viewer_with(f"f={small}", (big,), empty=True).scene.message
    for models in ((big, small), (small, big)):
        lines = viewer_with("", models, empty=True).scene.message.splitlines()
        assert [line.split(":")[0] for line in lines if "bounding box" in line] == ["loaded small.obj as a new object"]


def test_the_command_lines_models_are_placed_in_one_look_at_the_scene(tmp_path: Path,
                                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    """Each of the command line's models joining the ships was placed against a projection of the whole
    scene, and its message copied all those before it: 4,000 models took 123 s. Now one look serves
    the batch, and the messages keep their order, a failure's among them."""
    models = [octahedron(tmp_path / f"m{index}.obj", 1.0, (0.0, 60.0 * (index % 3), 0.0)) for index in range(40)]
    models.insert(7, tmp_path / "missing.obj")
    looks = []
    real = marraztu.model.scene.Scene.sights
    monkeypatch.setattr(marraztu.model.scene.Scene, "sights",
                        lambda scene, elements, *view: looks.append(len(elements)) or real(scene, elements, *view))
    lines = viewer_with("", tuple(models)).scene.message.splitlines()
    assert looks == [40]
    named = [line.split(" as a new")[0].removeprefix("loaded ").split(":")[0] for line in lines[-41:]]
    assert named == [Path(model).name if index != 7 else str(models[7]) for index, model in enumerate(models)]
    inside = "inside Rammer_255's bounding box"
    assert [inside in line for line in lines[-41:]] == [index != 7 and (index - (index > 7)) % 3 == 0
                                                         for index in range(41)]


def test_enclosers_of_many_are_each_ones_by_itself() -> None:
    """The batch's look for a box holding each element agrees with a plain pairwise look."""
    scene = load_builtin_scene()
    rng = np.random.default_rng(7)
    originals = list(scene.objects)
    for index in range(60):
        twin = originals[index % len(originals)]
        model = twin.model.copy()
        model[:3, :3] *= rng.uniform(0.05, 1.5)
        model[:3, 3] += rng.uniform(-40.0, 40.0, 3)
        scene.objects.append(type(twin)(name=f"o{index}", mesh=twin.mesh, material=twin.material, history=[model]))
    boxes = {id(element): marraztu.model.scene.world_box([element]) for element in scene.shown_elements()}
    expected = [next((other for other in scene.shown_elements() if other is not element
                      and (boxes[id(other)][0] <= boxes[id(element)][0]).all()
                      and (boxes[id(other)][1] >= boxes[id(element)][1]).all()), None)
                for element in scene.objects]
    assert scene.enclosers(scene.objects) == expected
    assert sum(found is not None for found in expected) > 5
    scene.modes.draw_all, loaded = False, scene.objects
    scene.objects = []  # nothing shown: nothing holds them (the soak test's random keys found it)
    assert scene.enclosers(loaded[:3]) == [None, None, None]


def test_a_box_placed_alone_is_the_same_box_placed_among_others() -> None:
    """A model added twice at one turned place is inside the other's box whether it is looked at alone
    (add_mesh, f) or with its batch (the command line's models): np.einsum summed a box alone in
    another order than a batch's, and an add_mesh of the twin said nothing in 72 of 200 turns."""
    rng = np.random.default_rng(3)
    mesh = build_mesh("m", rng.normal(size=(4, 3)) * 10.0, [[0, 1, 2], [0, 2, 3]])
    for _ in range(20):
        scene = empty_scene()
        model = placement(tuple(rng.uniform(-50.0, 50.0, 3)), tuple(rng.uniform(0.0, 360.0, 3)))
        first, twin = (SceneObject(name, mesh, DEFAULT_MATERIAL, [model.copy()]) for name in ("first", "twin"))
        scene.objects += [first, twin]
        assert np.array_equal(world_boxes([twin])[0], world_boxes(scene.objects)[1])
        assert scene.enclosers([twin]) == [first] and scene.enclosers(scene.objects) == [twin, first]


def test_placed_bounds_are_the_placed_corners_least_and_most_to_the_bit() -> None:
    """Scene.enclosers and the check of a scene changed by hand take a box's bounds without its corners:
    rounding a sum never reverses an order, so they are the same numbers, flat boxes, quarter turns and
    sums that overflow among them; where a turned side overflows, both hold a number that is not finite
    (refused), if not the same one (inf - inf is nan in a corner)."""
    rng = np.random.default_rng(5)
    models = rng.normal(size=(5000, 4, 4)) * 10.0 ** rng.integers(-8, 8, size=(5000, 1, 1))
    bounds = np.sort(rng.normal(size=(5000, 2, 3)), axis=1) * 10.0 ** rng.integers(-8, 8, size=(5000, 1, 1))
    bounds[::7, 1] = bounds[::7, 0]
    models[::5, :3, :3] = np.round(models[::5, :3, :3])
    models[::11, :3, :3] *= 1e300
    with np.errstate(over="ignore", invalid="ignore"):
        corners = marraztu.model.scene.placed_boxes(models, bounds)
        low, high = marraztu.model.scene.placed_bounds(models, bounds)
        sides_finite = np.isfinite(models[:, None, :3, :3] * bounds[:, :, None, :]).all(axis=(1, 2, 3))
    np.testing.assert_array_equal(low[sides_finite], corners.min(axis=1)[sides_finite])
    np.testing.assert_array_equal(high[sides_finite], corners.max(axis=1)[sides_finite])
    assert np.isinf(low[sides_finite]).any() and 0.8 < sides_finite.mean() < 1.0
    finite = np.isfinite(np.concatenate([low, high], axis=1)).all(axis=1)
    assert np.array_equal(finite, np.isfinite(corners).all(axis=(1, 2)))


def test_enclosers_agree_with_a_pairwise_look_where_boxes_meet_and_look_at_each_box_once(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Boxes turned by quarter turns, moved and scaled by whole numbers, meet face to face and match
    exactly: each element's first holder is a plain pairwise look's, a second camera (shown) and the
    viewer (never) among them, for the batch and for each element alone; and each call stacks the shown
    elements and the asked-for ones once, whatever their number (add_mesh asks for one)."""
    rng = np.random.default_rng(11)
    scene = empty_scene()
    cube = build_mesh("cube", np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 2.0) for z in (0.0, 1.0)]),
                      [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    for index in range(80):
        model = placement(tuple(rng.integers(-2, 3, 3).astype(float)), tuple(90.0 * rng.integers(0, 4, 3)))
        model[:3, :3] *= float(rng.choice([1.0, 2.0, 4.0]))
        element = SceneObject(f"e{index}", cube, DEFAULT_MATERIAL, [model])
        (scene.cameras if index % 20 == 19 else scene.objects).append(element)
    scene.selected_camera = 1  # the viewer: never a holder
    boxes = {id(element): marraztu.model.scene.world_box([element]) for element in scene.objects + scene.cameras}
    shown = scene.shown_elements()
    expected = [next((other for other in shown if other is not element
                      and (boxes[id(other)][0] <= boxes[id(element)][0]).all()
                      and (boxes[id(other)][1] >= boxes[id(element)][1]).all()), None)
                for element in scene.objects + scene.cameras]
    stacked: list[int] = []
    real = marraztu.model.scene._placements
    monkeypatch.setattr(marraztu.model.scene, "_placements", lambda elements: stacked.append(len(elements))
                        or real(elements))
    assert scene.enclosers(scene.objects + scene.cameras) == expected
    assert stacked == [len(shown), len(expected)]
    assert [scene.enclosers([element])[0] for element in scene.objects + scene.cameras] == expected
    assert 20 < sum(found is not None for found in expected) < 70
    assert scene.camera not in expected and any(camera in expected for camera in scene.cameras[2:])


@pytest.mark.parametrize("size,keys,outside", [((800, 800), "", True), ((1500, 500), "", False),
                                               ((1500, 500), "s", True)], ids=["square", "wide", "side by side"])
def test_outside_the_view_is_said_for_the_view_drawn(tmp_path: Path, size: tuple[int, int], keys: str,
                                                     outside: bool) -> None:
    """The hint assumed a view 3:1 wide: a model beside the ships, out of an 800x800 picture (and of
    each third of the side-by-side view), loaded without a word."""
    model = octahedron(tmp_path / "m.obj", 10.0, (300.0, 0.0, 0.0))
    with marraztu.Viewer(size=size) as v:
        v.press(keys).load(model)
        assert ("outside the view (. frames it)" in v.message) == outside, v.message


# Far from the origin, one turn about it swings a model further than the view is wide.
@pytest.mark.parametrize(("centre", "keys"), [((0.0, 300.0, 0.0), "x x"), ((300.0, 0.0, 0.0), "g Y Y"),
                                              ((0.0, 0.0, 0.0), "t x*30"), ((0.0, 0.0, 0.0), "c y*25")],
                         ids=["its own turn", "a global turn", "moved out with t", "the camera turned"])
def test_a_key_that_takes_the_selected_model_out_of_view_says_so_once_and_dot_frames_it(
        tmp_path: Path, centre: tuple[float, float, float], keys: str) -> None:
    """A model whose file places it 300 units off turned with one key, or one moved off with t, or the
    camera turned away: the picture went blank and the message said nothing."""
    viewer = viewer_with("", (octahedron(tmp_path / "far.obj", 10.0, centre),), empty=True)
    scene, aspect = viewer.scene, viewer.narrowest_aspect()
    told = []
    for key in parse_key_sequence(keys):
        was = scene.sight(scene.object, aspect)
        viewer.press(key)
        lost = was is Sight.SEEN and scene.sight(scene.object, aspect) is Sight.OUTSIDE
        assert (scene.message == "far is now outside the view (. frames it)") == lost, (key, scene.message)
        told.append(lost)
    assert told.count(True) == 1
    viewer.press(parse_key_sequence(".")[0])
    assert scene.sight(scene.object, aspect) is Sight.SEEN and scene.message == "framed far"


@pytest.mark.parametrize("gesture", ["pan", "wheel"])
def test_a_mouse_gesture_that_takes_the_selected_model_out_of_view_says_so_once(tmp_path: Path,
                                                                                 gesture: str) -> None:
    """A right drag that slid the model off the window, or wheel notches away until it was a speck,
    left a blank view and no word, where a key saying the same said so."""
    viewer = viewer_with("", (octahedron(tmp_path / "m.obj", 10.0),), empty=True)
    viewer.scene.message = "loaded m.obj"
    moves = {"pan": lambda scene: commands.pan_view(scene, 40, 0, 600),
             "wheel": lambda scene: commands.dolly_view(scene, -3)}[gesture]
    told = []
    for _ in range(200):
        viewer.move_by_mouse(moves)
        told.append(viewer.scene.message)
    lost = [index for index, message in enumerate(told) if message != "loaded m.obj"]
    where = {"pan": "outside the view", "wheel": "too small to see from here"}[gesture]
    assert lost and set(told[lost[0]:]) == {f"m is now {where} (. frames it)"}, told[lost[0] - 1:lost[0] + 2]


@pytest.mark.parametrize("said_by", ["the mouse", "a key"])
def test_a_mouse_gesture_that_brings_the_model_back_into_view_takes_the_notice_back(tmp_path: Path,
                                                                                     said_by: str) -> None:
    """A right drag slid the model off the window and back on: 'm is now outside the view' stayed up
    over the model in plain view, until the next key."""
    viewer = viewer_with("c t" if said_by == "a key" else "", (octahedron(tmp_path / "m.obj", 10.0),), empty=True)
    scene, aspect = viewer.scene, viewer.narrowest_aspect()
    for _ in range(100):  # the camera slides left, by a press or a drag's event at a time
        if scene.sight(scene.object, aspect) is not Sight.SEEN:
            break
        if said_by == "a key":
            viewer.press(parse_key_sequence("X")[0])
        else:
            viewer.move_by_mouse(lambda moved: commands.pan_view(moved, 40, 0, 600))
    assert scene.message == "m is now outside the view (. frames it)"
    commands.end_view_gesture(scene)
    for _ in range(100):
        viewer.move_by_mouse(lambda moved: commands.pan_view(moved, -40, 0, 600))
        if scene.sight(scene.object, aspect) is Sight.SEEN:
            break
    assert scene.sight(scene.object, aspect) is Sight.SEEN and scene.message == ""


def test_a_mouse_move_that_brings_a_model_loaded_out_of_view_into_it_takes_back_those_words(tmp_path: Path) -> None:
    """A model loaded out of view and dragged into it kept ', outside the view (. frames it)' in its load
    message, over the model in plain view; the rest of the message stays."""
    near = octahedron(tmp_path / "near.obj", 10.0)
    far = octahedron(tmp_path / "far.obj", 10.0, (0.0, 1e4, 0.0))
    viewer = viewer_with("", (near,), empty=True)
    scene, aspect = viewer.scene, viewer.narrowest_aspect()
    viewer.press(parse_key_sequence(f"f={far}")[0])
    said = scene.message.replace(", outside the view (. frames it)", "", 1)
    assert said != scene.message and said.startswith("loaded far.obj as a new object: ")

    def drag_it_into_view(moved: Scene) -> None:  # a mouse move says nothing of its own
        message = moved.message
        commands.frame_selected(moved, viewer)
        moved.message = message

    viewer.move_by_mouse(lambda moved: commands.pan_view(moved, 1, 0, 600))  # still out: kept
    assert scene.sight(scene.object, aspect) is not Sight.SEEN and scene.message.endswith("(. frames it)")
    viewer.move_by_mouse(drag_it_into_view)
    assert scene.sight(scene.object, aspect) is Sight.SEEN and scene.message == said


def test_a_model_deleted_while_said_out_of_view_is_not_kept(tmp_path: Path) -> None:
    """The record of the words that a model is out of view held the model itself: deleted, its mesh stayed
    in memory until another model was said out of view."""
    near = octahedron(tmp_path / "near.obj", 10.0)
    far = octahedron(tmp_path / "far.obj", 10.0, (0.0, 1e4, 0.0))
    viewer = viewer_with(f"f={far}", (near,), empty=True)
    assert viewer.scene.message.endswith("outside the view (. frames it)")
    mesh = weakref.ref(viewer.scene.object.mesh)
    viewer.press(parse_key_sequence("DELETE")[0])
    gc.collect()
    assert [obj.name for obj in viewer.scene.objects] == ["near"] and mesh() is None


def test_a_file_loaded_twice_is_said_inside_the_other_of_its_name(tmp_path: Path) -> None:
    """It said 'big.obj ... inside big's bounding box', of two objects both named big."""
    model = octahedron(tmp_path / "big.obj", 10.0)
    viewer = viewer_with("", (model,), empty=True)
    viewer.press(parse_key_sequence(f"f={model}")[0])
    assert "inside the other big's bounding box" in viewer.scene.message, viewer.scene.message


def test_a_key_that_leaves_the_model_in_view_or_changes_the_selection_says_nothing_of_it(tmp_path: Path) -> None:
    near = octahedron(tmp_path / "near.obj", 10.0)
    far = octahedron(tmp_path / "far.obj", 10.0, (0.0, 1e4, 0.0))
    viewer = viewer_with("x y z t x", (near,), empty=True)
    assert viewer.scene.message == ""
    viewer.press(parse_key_sequence(f"f={far}")[0])  # far is selected: the one out of view is another
    assert "is now" not in viewer.scene.message and "outside the view (. frames it)" in viewer.scene.message
    viewer.press(parse_key_sequence("TAB")[0])
    assert viewer.scene.message == ""


def test_the_out_of_view_notice_looks_at_the_selected_model_alone(tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """One box test after a key, whatever the scene holds (a second, of the view before it, only where
    the model is out of view now): no key costs a pass over the scene."""
    viewer = viewer_with("", tuple(octahedron(tmp_path / f"m{index}.obj", 1.0, (3.0 * index, 0.0, 0.0))
                                   for index in range(30)))
    looked_at: list[int] = []
    real = marraztu.model.scene.world_boxes
    monkeypatch.setattr(marraztu.model.scene, "world_boxes",
                        lambda elements: looked_at.append(len(elements)) or real(elements))
    monkeypatch.setattr(marraztu.model.scene.Scene, "near_plane", lambda *_: pytest.fail("a pass over the scene"))
    viewer.press(parse_key_sequence("x")[0])
    assert looked_at == [1]


def test_home_returns_to_the_start_and_u_takes_it_back(tmp_path: Path) -> None:
    start = picture(tmp_path, "", empty=False, name="start.png")
    moved = picture(tmp_path, "c t x*5 Z*3 r y c c", empty=False, name="moved.png")
    assert np.array_equal(picture(tmp_path, "c t x*5 Z*3 r y c c HOME", empty=False, name="home.png"), start)
    assert np.array_equal(picture(tmp_path, "c t x*5 Z*3 r y c c HOME u", empty=False, name="u.png"), moved)


def test_a_camera_loaded_with_f_stands_outside_the_scene_looking_at_it(tmp_path: Path) -> None:
    viewer = viewer_with(f"c f={octahedron(tmp_path / 'cam.obj', 5.0)}")
    camera = viewer.scene.camera
    centre, radius = bounding_sphere(viewer.scene.objects)
    to_centre = centre - camera.origin
    assert camera.name == "cam" and np.linalg.norm(to_centre) > radius
    assert np.dot(camera.forward, to_centre / np.linalg.norm(to_centre)) == pytest.approx(1.0)


def test_the_models_of_the_command_line_are_framed_together(tmp_path: Path) -> None:
    """A small model first and a large one beside it: the camera frames both, outside the large one,
    and HOME comes back to that view; beside the built-in scene's ships, they leave the view alone."""
    small = octahedron(tmp_path / "small.obj", 1.0)
    large = tmp_path / "large.obj"
    large.write_text("".join(f"v {x + 300:g} {y:g} {z:g}\n" for x, y, z in np.loadtxt(small, usecols=(1, 2, 3),
                                                                                   max_rows=6) * 50)
                     + "".join(line + "\n" for line in small.read_text().splitlines() if line.startswith("f")))
    viewer = viewer_with("", (small, large), empty=True)
    camera = viewer.scene.camera
    centre, radius = bounding_sphere(viewer.scene.objects)
    to_centre = centre - camera.origin
    assert np.linalg.norm(to_centre) > radius and len(camera.history) == 1
    assert np.dot(camera.forward, to_centre / np.linalg.norm(to_centre)) == pytest.approx(1.0)
    built_in = viewer_with("", (small, large))
    assert np.array_equal(built_in.scene.camera.model, viewer_with("").scene.camera.model)


def test_models_of_the_command_line_too_small_to_see_framed_together_are_said(tmp_path: Path) -> None:
    """Two 10-unit boxes 100,000 units apart, framed together, each under a thousandth of the view: the
    picture was empty and the messages said only that both loaded."""
    near = octahedron(tmp_path / "near.obj", 5.0)
    far = octahedron(tmp_path / "far.obj", 5.0, (1e5, 0.0, 0.0))
    big = octahedron(tmp_path / "big.obj", 500.0, (1000.0, 0.0, 0.0))
    message = viewer_with("", (near, far), empty=True).scene.message
    assert "near, far: too small to see framed together (TAB selects one, . frames it)" in message
    assert "too small" not in viewer_with("", (near, big), empty=True).scene.message  # near is seen


def nearest_depth(scene, element) -> float:
    """How far in front of the eye the element's nearest vertex is."""
    world = element.mesh.positions @ element.model[:3, :3].T + element.model[:3, 3]
    return float(((world - scene.eye_position()) @ scene.viewer.forward).min())


def test_the_near_plane_is_the_specifications_for_its_scene_small_for_small_models_and_far_for_huge_ones(
        tmp_path: Path) -> None:
    assert viewer_with("").scene.near_plane() == 5.0
    unit = viewer_with("", (octahedron(tmp_path / "u.obj", 1.0),), empty=True).scene
    assert 0.0 < unit.near_plane() < nearest_depth(unit, unit.object)
    small = viewer_with("", (octahedron(tmp_path / "m.obj", 1e-3),), empty=True).scene
    assert small.near_plane() == pytest.approx(1e-3 * unit.near_plane())  # the same view, in its units
    huge = viewer_with("", (octahedron(tmp_path / "h.obj", 1e7),), empty=True).scene
    assert nearest_depth(huge, huge.object) / 100 < huge.near_plane() < nearest_depth(huge, huge.object)
    beside_the_ships = viewer_with("", (octahedron(tmp_path / "h.obj", 1e7),)).scene
    ships = [obj for obj in beside_the_ships.objects if obj.name != "h"]
    # The eye is deep inside the huge model: the ships, all far ahead, keep it short of them.
    assert 5.0 < beside_the_ships.near_plane() < min(nearest_depth(beside_the_ships, ship) for ship in ships)
    camera = octahedron(tmp_path / "cam.obj", 5.0)
    with_a_camera_in_view = viewer_with(f"c f={camera}", (tmp_path / "h.obj",), empty=True)
    assert len(with_a_camera_in_view.scene.cameras) == 2
    scene = with_a_camera_in_view.scene
    other = next(camera for camera in scene.cameras if camera is not scene.viewer)
    assert scene.near_plane() < nearest_depth(scene, other)  # it stands clear of the other's body


def test_the_near_plane_keeps_clear_of_a_small_model_looked_at_from_close_by(tmp_path: Path) -> None:
    """A 2-unit model above the built-in ships: `.` frames it 2 units away and the wheel comes closer;
    SPEC 5's near plane of 5 units cut it away whole (an empty picture)."""
    model = octahedron(tmp_path / "two.obj", 1.0, (0.0, 60.0, 0.0))
    framed = viewer_with(".", (model,)).scene
    assert framed.object.name == "two" and 0.0 < framed.near_plane() < nearest_depth(framed, framed.object)
    pixels = picture(tmp_path, ".", (model,), empty=False)
    assert (pixels != BACKGROUND).any(axis=2).mean() > 0.1
    while nearest_depth(framed, framed.object) > framed.object.mesh.size / 10:
        assert 0.0 < framed.near_plane() < nearest_depth(framed, framed.object)
        commands.dolly_view(framed, 1)


def test_the_near_plane_keeps_within_a_sheet_the_eye_is_inside(tmp_path: Path) -> None:
    """A sheet 1e6 wide and 1 thick loaded beside the ships holds the start camera: its faces lie half a
    unit above and below the eye, and a near plane of a thousandth of the sheet's diagonal (1,414) cut them
    away, an empty picture with `d`."""
    sheet = box(tmp_path / "sheet.obj", (1e6, 1.0, 1e6))
    scene = viewer_with("d", (sheet,)).scene
    assert 0.0 < scene.near_plane() < 0.5
    pixels = picture(tmp_path, "d", (sheet,), empty=False)
    assert (pixels != BACKGROUND).any(axis=2).mean() > 0.9  # its inside, above and below


@pytest.mark.parametrize("unit", [1e-3, 1e3], ids=["kilometres", "millimetres"])
def test_the_same_scene_in_other_units_draws_the_same_close_up_inside_and_in_the_depth_view(
        tmp_path: Path, unit: float) -> None:
    """The near plane is on the scene's scale: the wheel up to a cube's face, a room's wall a metre
    off, and the depth view draw as in metres (their near planes were 5 units in each)."""
    def close_up(scale: float) -> np.ndarray:
        with marraztu.Viewer(size=SIZE, empty=True) as viewer:
            viewer.load(box(tmp_path / f"cube{scale}.obj", (10 * scale,) * 3))
            for _ in range(10):  # the eye ends 0.44 m from the face
                commands.dolly_view(viewer.scene, 1)
            return np.asarray(viewer.render().convert("RGB")).astype(int)

    def inside(scale: float) -> np.ndarray:
        room = box(tmp_path / f"room{scale}.obj", (10 * scale, 3 * scale, 10 * scale), inward=True)
        return picture(tmp_path, "c t Z*34", (room,), name=f"room{scale}.png")  # a metre from the far wall

    def depth(scale: float) -> np.ndarray:
        return picture(tmp_path, "v*8", (box(tmp_path / f"d{scale}.obj", (20 * scale,) * 3),), name=f"d{scale}.png")

    for draw in (close_up, inside, depth):
        metres, other = draw(1.0), draw(unit)
        assert (metres != BACKGROUND).any(axis=2).mean() > 0.2, draw.__name__
        assert np.abs(other - metres).max() <= 1, draw.__name__


@pytest.mark.parametrize("ahead", [1e-15, 0.0, 2.0])
def test_a_lights_marker_asks_nothing_of_the_near_plane(ahead: float) -> None:
    """A bulb a hair in front of the eye brought the near plane to 0 (a projection of NaNs, as a
    spotlight carried by the object looked through with `C` did)."""
    viewer = viewer_with("c c TAB")
    scene = viewer.scene
    assert scene.light.name == "bulb"
    scene.light.position = scene.eye_position() + ahead * scene.viewer.forward
    assert scene.near_plane() == 5.0
    assert np.isfinite(scene.projection_matrix(1.0)).all()


@pytest.mark.parametrize("unit", [1e-3, 1e3], ids=["kilometres", "millimetres"])
def test_the_lights_and_the_cameras_body_follow_a_lone_models_units(tmp_path: Path, unit: float) -> None:
    """The bulb stayed 200 units up (inside a cube in millimetres, 200 km above one in kilometres) and
    the camera's body 18 units long: the same cube was lit otherwise, and turned to look back at the
    camera (C) saw its body fill the view."""
    for keys in ("1 3 F", "C r y*31 1"):
        metres = picture(tmp_path, keys, (box(tmp_path / "m.obj", (60.0,) * 3),), name="m.png")
        other = picture(tmp_path, keys, (box(tmp_path / "o.obj", (60.0 / unit,) * 3),), name="o.png")
        assert (metres != BACKGROUND).any(axis=2).mean() > 0.002, keys
        assert np.abs(other - metres).max() <= 1, keys


def test_the_lights_follow_a_lone_model_whatever_the_camera_did_but_a_placed_light_stays() -> None:
    """The fit waited for a camera not yet moved (a nudge left the bulb 200 units over a 0.02 cube);
    a light the person placed, with the keys or from Python, stays where they put it."""
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float) * 0.01
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    for before in ("", "c t x c c"):
        with marraztu.Viewer(size=SIZE, empty=True) as viewer:
            viewer.press(before)
            viewer.add_mesh(cube, quads)
            assert np.allclose(viewer.scene.lights[1].position, [0.0, 0.2, 0.0]), before
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.press("c c TAB t x")  # the bulb 5 along x
        viewer.add_mesh(cube, quads)
        assert np.allclose(viewer.scene.lights[1].position, [5.0, 200.0, 0.0])
        viewer.press("u")
        assert np.allclose(viewer.scene.lights[1].position, [0.0, 200.0, 0.0])
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.scene.lights[1].position = np.array([0.0, 0.05, 0.0])  # placed from Python, in the model's units
        viewer.add_mesh(cube, quads)
        assert np.allclose(viewer.scene.lights[1].position, [0.0, 0.05, 0.0])


def test_a_camera_loaded_into_a_lone_models_scene_stands_clear_of_the_first(tmp_path: Path) -> None:
    """It stood where the first camera frames the model, inside that camera's body: a red picture."""
    camera = box(tmp_path / "cam.obj", (0.05,) * 3)
    pixels = picture(tmp_path, f"c f={camera}", (box(tmp_path / "m.obj", (60.0,) * 3),))
    red = (pixels[..., 0] > 200) & (pixels[..., 1] < 50) & (pixels[..., 2] < 50)
    assert red.mean() < 0.05 and (pixels != BACKGROUND).any(axis=2).mean() > 0.02


def test_a_small_model_out_of_view_leaves_the_picture_alone(tmp_path: Path) -> None:
    """A millimetre cube beside the flight path, 20 units to the side: the near plane keeps clear of
    what is in view alone (it came in to 0.0002 for it, and the ships showed their backs through)."""
    bolt = box(tmp_path / "bolt.obj", (0.001,) * 3, (20.0, 0.0, 100.0))
    without, beside = (picture(tmp_path, "c t Z*10", models, empty=False, name=f"{len(models)}.png")
                       for models in ((), (bolt,)))
    assert np.array_equal(without, beside)


def plate_with_a_label(path: Path, unit: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Path:
    """A white plate 50 metres across and a green label 20 metres across lying 2 millimetres above it,
    in `unit`s of a metre, about `centre`, tilted a radian toward the start camera."""
    plate, label, proud = 25.0 / unit, 10.0 / unit, 0.002 / unit
    corners = np.array([(-plate, 0, -plate), (plate, 0, -plate), (plate, 0, plate), (-plate, 0, plate),
                        (-label, proud, -label), (label, proud, -label), (label, proud, label), (-label, proud, label)])
    tilt = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(1.0), -np.sin(1.0)], [0.0, np.sin(1.0), np.cos(1.0)]])
    placed = corners @ tilt.T + centre
    path.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r} {int(row < 4)} 1 {int(row < 4)}\n"
                            for row, (x, y, z) in enumerate(placed)) + "f 1 4 3 2\nf 5 8 7 6\n")
    return path


def green_share(pixels: np.ndarray) -> float:
    """How much of the picture the green label covers."""
    return float(((pixels[..., 1] > 2 * pixels[..., 0] + 10) & (pixels[..., 1] > 2 * pixels[..., 2] + 10)).mean())


def test_a_model_in_millimetres_keeps_the_depth_precision_it_has_in_metres(tmp_path: Path) -> None:
    """The near plane moves out where everything shown is far: at 5 units, 64 metres of millimetres
    away, the plate's depth covered the label 2 millimetres above it."""
    metres = picture(tmp_path, "", (plate_with_a_label(tmp_path / "m.obj", 1.0),), name="m.png")
    millimetres = picture(tmp_path, "", (plate_with_a_label(tmp_path / "mm.obj", 1e-3),), name="mm.png")
    assert green_share(metres) > 0.01, "the green label shows in metres"
    assert np.abs(millimetres - metres).max(axis=2).mean() < 1.0, "the same picture, but for rounding"


@pytest.mark.parametrize("keys", [".", "p ."], ids=["perspective", "parallel"])
def test_a_molecule_framed_among_the_ships_shows_them_behind_it_as_a_model_in_metres_does(
        tmp_path: Path, keys: str) -> None:
    """Framed 2 micrometres off, the near plane is 0.1 micrometre: Rammer's wall 50 metres behind lay past
    a 24-bit depth buffer's last step (1 - near / depth rounds to 1, the cleared depth) and was not drawn,
    the picture blue where a model in metres, framed alike, showed it red behind."""
    metres = picture(tmp_path, keys, (octahedron(tmp_path / "m.obj", 1.0),), empty=False, name="m.png")
    molecule = picture(tmp_path, keys, (octahedron(tmp_path / "mol.obj", 1e-6),), empty=False, name="mol.png")
    assert (metres != BACKGROUND).any(axis=2).mean() > 0.9  # Rammer's wall behind it
    assert (np.abs(molecule - metres).max(axis=2) > 1).mean() < 0.001


def test_a_view_in_depth_slices_looks_at_the_shown_boxes_once_with_the_light_marker_too(
        tmp_path: Path, offscreen, monkeypatch) -> None:
    """The light marker takes the whole depth's lens, which is its slices' together: made again from the
    scene, it looked at every shown box a second time in each frame."""
    from dataclasses import replace

    from marraztu.model.scene import Target

    scene = viewer_with(".", (octahedron(tmp_path / "mol.obj", 1e-6),)).scene
    scene.modes.target = Target.LIGHTS
    slices = scene.depth_slices(1.0)
    assert len(slices) > 1 and replace(slices[0], near=slices[-1].near) == scene.lens(1.0)
    looks = []
    shown_boxes = Scene._shown_boxes
    monkeypatch.setattr(Scene, "_shown_boxes", lambda *args, **kwargs: looks.append(1) or shown_boxes(*args, **kwargs))
    offscreen(scene)
    assert len(looks) == 1


def test_the_probe_outline_in_a_farther_depth_slice_leaves_the_nearer_slice_depth_tested(
        tmp_path: Path, offscreen) -> None:
    """The probe's outline ends with the depth test off; drawn in the farther slice, it left the nearer
    slice's surfaces drawn in the order they come, the molecule's back faces over its front."""
    scene = viewer_with(".", (octahedron(tmp_path / "mol.obj", 1e-6),)).scene
    assert len(scene.depth_slices(1.0)) > 1 and scene.object is not None
    plain = offscreen(scene)
    scene.modes.probe = True
    probed = offscreen(scene)
    outline = (probed != plain).any(axis=2)
    assert outline.mean() < 0.05, "the outline and its dots alone differ"


def test_clearing_a_depth_slice_restores_the_colour_mask_when_the_clear_fails() -> None:
    """A nearer depth slice clears the depth alone, the colour masked off: a clear that raised left the
    framebuffer's colour masked, and so every later picture drawn into it blank."""
    from types import SimpleNamespace

    from marraztu.errors import ViewerError
    from marraztu.model.scene import Shading
    from marraztu.model.viewports import View
    from marraztu.render.renderer import Renderer

    class Framebuffer:
        color_mask = (True, True, True, True)

        def clear(self, **kwargs: object) -> None:
            raise ViewerError("the GPU refused a clear")

        def use(self) -> None:
            pass

    fbo = Framebuffer()
    with pytest.raises(ViewerError, match="refused a clear"):
        Renderer._clear_depth(SimpleNamespace(ctx=SimpleNamespace(fbo=fbo)), View((0, 0, 8, 8), Shading.PHONG))
    assert fbo.color_mask == (True, True, True, True)


@pytest.mark.parametrize("unit,centre", [(1e6, (0.0, 0.0, 0.0)), (1.0, (4e6, -3e6, 7.0))],
                         ids=["in micrometres", "5,000 km out"])
def test_in_parallel_projection_the_label_shows_whatever_the_units_and_place(
        tmp_path: Path, unit: float, centre: tuple[float, float, float]) -> None:
    """Parallel projection's depth buffer steps evenly from near to far: a far plane 1,000 units out,
    or beyond the lights at the origin, made its steps coarser than the 2 millimetres."""
    metres = picture(tmp_path, "p", (plate_with_a_label(tmp_path / "m.obj", 1.0),), name="m.png")
    odd = picture(tmp_path, "p", (plate_with_a_label(tmp_path / "odd.obj", unit, centre),), name="odd.png")
    assert green_share(metres) > 0.01, "the green label shows in metres"
    assert np.abs(odd - metres).max(axis=2).mean() < 1.0, "the same picture, but for rounding"


@pytest.mark.parametrize("size", [1e5, 1e7, 1e9])
def test_a_huge_model_shows_as_a_small_one_does(tmp_path: Path, size: float) -> None:
    """Its back faces (red) stay behind its front ones: from 5 units to the distance that frames it,
    the depth buffer could not tell them apart, and at 1e9 it put everything at the far plane."""
    keys = "y*2 x*3"  # ambient light alone: point lights stay where they are whatever the model's size
    small = picture(tmp_path, keys, (octahedron(tmp_path / "small.obj", 10.0),), name="small.png")
    huge = picture(tmp_path, keys, (octahedron(tmp_path / "huge.obj", size),), name="huge.png")
    assert (small != BACKGROUND).any(axis=2).sum() > 0.1 * small.shape[0] * small.shape[1]
    assert np.abs(huge - small).max(axis=2).mean() < 1.0, "the same picture, but for rounding"


@pytest.mark.parametrize("distance", [4e6, 4e7, 4e9])
def test_models_far_from_the_origin_show_as_the_same_models_at_it_do(tmp_path: Path, distance: float) -> None:
    """The GPU's rows of a far model are measured from its centre and the world's positions from the
    eye, both in 64-bit numbers, so its 32-bit numbers stay small: 4e7 units away the corners of a
    10-unit model would otherwise land on steps of 4 units. Two models of one site, of different
    sizes, keep their places."""
    site = np.array([distance, -0.75 * distance, 7.0])
    models = {"near": np.zeros(3), "far": site}
    pictures = {}
    for name, centre in models.items():
        small = octahedron(tmp_path / f"{name}_small.obj", 10.0, tuple(centre))
        large = octahedron(tmp_path / f"{name}_large.obj", 60.0, tuple(centre + (90.0, 40.0, -30.0)))
        pictures[name] = picture(tmp_path, "", (small, large), name=f"{name}.png")
    near, far = pictures["near"], pictures["far"]
    assert (near != BACKGROUND).any(axis=2).sum() > 0.03 * near.shape[0] * near.shape[1]
    assert np.abs(far - near).max(axis=2).mean() < 1.0, "the same picture, but for rounding"


def test_a_small_model_on_a_large_one_far_out_keeps_its_place(tmp_path: Path) -> None:
    """A 40-unit house on a 2,800-unit terrain, each in its own file, 5.6e6 units out: the terrain is
    not 4,096 of its sizes out, but past FAR_AWAY it is measured from its centre as the house is."""
    pictures = {}
    for name, centre in (("near", np.zeros(3)), ("far", np.array([4e6, -3e6, 2.4e6]))):
        terrain = octahedron(tmp_path / f"{name}_terrain.obj", 1400.0, tuple(centre))
        house = octahedron(tmp_path / f"{name}_house.obj", 20.0, tuple(centre + (30.0, 1400.0, 0.0)))
        pictures[name] = picture(tmp_path, ".", (terrain, house), name=f"{name}.png")  # framed on the house
    assert (pictures["near"] != BACKGROUND).any(axis=2).sum() > 0.1 * SIZE[0] * SIZE[1]
    assert np.abs(pictures["far"] - pictures["near"]).max(axis=2).mean() < 1.0


@pytest.mark.parametrize("distance", [1e5, 1e8, 1e10])
def test_a_small_model_a_scene_places_far_out_shows_as_at_the_origin(tmp_path: Path, distance: float) -> None:
    """A scene file's position, not the model's own coordinates: the eye beside a 1-unit triangle at
    1e8 was 1e8 out in 32-bit numbers, and nothing was drawn."""
    (tmp_path / "tri.obj").write_text("v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nf 1 2 3\n")
    pictures = []
    for place in (0.0, distance):
        scene = tmp_path / f"at{place:g}.toml"
        scene.write_text(f'[[cameras]]\nmodel = "tri.obj"\nposition = [{place}, 0, 5]\n'
                         f'[[objects]]\nmodel = "tri.obj"\nposition = [{place}, 0, 0]\n')
        out = take_screenshot(StartOptions(scene_file=scene), tmp_path / f"at{place:g}.png", (120, 90), keys="")
        pictures.append(np.asarray(Image.open(out).convert("RGB")))
    assert (pictures[0] != BACKGROUND).any(axis=2).sum() > 30
    assert np.array_equal(pictures[1], pictures[0])


def test_only_a_model_far_from_the_origin_is_measured_from_its_centre_on_the_gpu(tmp_path: Path) -> None:
    near = load_model(octahedron(tmp_path / "near.obj", 10.0, (1e4, 0.0, 0.0)))  # 290 sizes out
    far = load_model(octahedron(tmp_path / "far.obj", 10.0, (1e6, 5.0, 0.0)))
    far_away = load_model(octahedron(tmp_path / "far_away.obj", 1e3, (7e4, 0.0, 0.0)))  # 20 sizes, past FAR_AWAY
    assert not near.gpu_origin.any() and near.gpu_positions() is near.positions
    assert far.gpu_origin.tolist() == [1e6, 5.0, 0.0]
    assert np.abs(far.gpu_positions()).max() == 10.0
    assert far_away.gpu_origin.tolist() == [7e4, 0.0, 0.0]


def test_the_parts_of_a_mesh_are_measured_from_its_own_gpu_origin() -> None:
    """A 1-unit part 60 units out on a 140-unit model at the origin is not far of its own: every
    part of a mesh is drawn from the whole's origin."""
    from dataclasses import replace

    from marraztu.model.build import build_mesh
    from marraztu.model.mesh import MeshMaterial

    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64)
    mesh = build_mesh("two", np.vstack([square * 140 - 70, square * 0.01 + (60, 0, 0)]), [[0, 1, 2, 3], [4, 5, 6, 7]])
    mesh = replace(mesh, materials=(MeshMaterial("a"), MeshMaterial("b")), face_material=np.array([0, 1], np.int32))
    assert [mesh.part_mesh(part).gpu_origin.tolist() for part in mesh.drawn_parts()] == [[0, 0, 0], [0, 0, 0]]


# --- the mouse -----------------------------------------------------------------------------------
def scene_with_model(tmp_path: Path):
    return viewer_with("", (octahedron(tmp_path / "m.obj", 20.0),), empty=True).scene


def test_orbit_keeps_the_distance_to_the_object_and_turns_the_view_toward_it(tmp_path: Path) -> None:
    scene = scene_with_model(tmp_path)
    centre = scene.object.centre
    before = np.linalg.norm(scene.camera.origin - centre)
    commands.orbit_view(scene, 120, -45, SIZE)
    assert np.linalg.norm(scene.camera.origin - centre) == pytest.approx(before)
    to_centre = (centre - scene.camera.origin) / before
    assert np.dot(scene.camera.forward, to_centre) == pytest.approx(1.0)
    assert scene.camera.origin[0] < 0  # dragged right: the camera swings left, the model turns right


def _turned_deg(before: np.ndarray, after: np.ndarray) -> float:
    cosine = np.dot(before, after) / np.linalg.norm(before) / np.linalg.norm(after)
    return math.degrees(math.acos(np.clip(cosine, -1.0, 1.0)))


@pytest.mark.parametrize("window", [(800, 600), (300, 1000)])
def test_orbit_turns_as_vtks_trackball_200_degrees_across_the_window(tmp_path: Path, window: tuple[int, int]) -> None:
    """A drag turned 0.57 degrees a pixel whatever the window's size: 90 pixels turned 52 degrees. As
    VTK's trackball (Rotate(): -20 / size times MotionFactor 10), half the window's width turns the view
    100 degrees, and half its height 100 degrees the other way."""
    for dx, dy in ((window[0] / 2, 0), (0, window[1] / 2)):
        scene = scene_with_model(tmp_path)
        centre = scene.object.centre
        before = scene.camera.origin - centre
        commands.orbit_view(scene, dx, dy, window)
        assert _turned_deg(before, scene.camera.origin - centre) == pytest.approx(100.0)


def test_pan_slides_the_camera_in_its_own_plane_following_the_cursor(tmp_path: Path) -> None:
    scene = scene_with_model(tmp_path)
    before = scene.camera.model.copy()
    commands.pan_view(scene, 80, 0, SIZE[1])  # half the view's height in pixels, sideways
    moved = scene.camera.model
    assert np.array_equal(moved[:3, :3], before[:3, :3])
    depth = np.linalg.norm(before[:3, 3] - scene.object.centre)
    assert moved[0, 3] - before[0, 3] == pytest.approx(-depth * np.tan(np.radians(45)))  # half the view


def test_pan_with_the_selected_object_behind_the_eye_follows_the_cursor_at_the_scenes_depth(tmp_path: Path) -> None:
    """A model in millimetres loaded 12 km behind the built-in camera, selected: half the view's width
    of a drag moved the camera as at the near plane's depth, 20 units (5 in a 400x400 window), where
    with a ship selected it moves 150, the ships' depth."""
    behind = octahedron(tmp_path / "behind.obj", 100.0, (5000.0, -3000.0, 12000.0))
    moved = []
    for models in ((), (behind,)):
        scene = viewer_with("", models).scene
        before = scene.camera.origin
        commands.pan_view(scene, SIZE[0] / 2, 0, SIZE[1])
        moved.append(np.linalg.norm(scene.camera.origin - before))
    assert moved[1] == pytest.approx(moved[0], rel=0.2)


def test_the_wheel_dollies_toward_the_object_and_never_through_it(tmp_path: Path) -> None:
    scene = scene_with_model(tmp_path)
    centre = scene.object.centre
    before = np.linalg.norm(scene.camera.origin - centre)
    for _ in range(20):
        commands.dolly_view(scene, 1)
    after = np.linalg.norm(scene.camera.origin - centre)
    assert after == pytest.approx(before * commands.DOLLY_PER_NOTCH ** 20)
    for _ in range(200):
        commands.dolly_view(scene, 1)
    closest = np.linalg.norm(scene.camera.origin - centre)
    assert closest == pytest.approx(commands.DOLLY_CLOSEST * scene.object.mesh.size)


@pytest.mark.parametrize("centre", [(0.0, 0.0, 0.0), (5000.0, -3000.0, 12000.0)])
def test_the_wheel_comes_back_out_after_any_number_of_notches_in(tmp_path: Path,
                                                                 centre: tuple[float, float, float]) -> None:
    """A 200 mm model at (5000, -3000, 12000): 400 notches in left the camera 7e-12 from its centre,
    where a notch out no longer changed a 64-bit coordinate, and 1650 notches out never moved it; at
    the origin 400 notches in took 400 out again."""
    scene = viewer_with("", (octahedron(tmp_path / "m.obj", 100.0, centre),), empty=True).scene
    before = np.linalg.norm(scene.camera.origin - scene.object.centre)
    for _ in range(400):
        commands.dolly_view(scene, 1)
    for _ in range(100):
        commands.dolly_view(scene, -1)
    assert np.linalg.norm(scene.camera.origin - scene.object.centre) > before


def test_in_parallel_projection_the_wheel_zooms_and_u_and_home_take_the_zoom_back(tmp_path: Path) -> None:
    """Parallel projection's picture does not change with the distance: the wheel moving the camera
    only cut into the model, and `u` and HOME left the view zoomed."""
    scene = viewer_with("p", (octahedron(tmp_path / "m.obj", 20.0),), empty=True).scene
    start, half_height = scene.camera.model.copy(), scene.modes.parallel_half_height
    for _ in range(30):
        commands.dolly_view(scene, 1)
    assert np.array_equal(scene.camera.model, start)
    assert scene.modes.parallel_half_height == pytest.approx(half_height * commands.DOLLY_PER_NOTCH ** 30)
    commands.end_view_gesture(scene)
    dispatch(scene, parse_key_sequence("u")[0], RecordingHost())
    assert scene.modes.parallel_half_height == half_height
    commands.dolly_view(scene, 5)
    dispatch(scene, parse_key_sequence("HOME")[0], RecordingHost())
    assert scene.modes.parallel_half_height == pytest.approx(half_height)
    dispatch(scene, parse_key_sequence("u")[0], RecordingHost())
    assert scene.modes.parallel_half_height == pytest.approx(half_height * commands.DOLLY_PER_NOTCH ** 5)


@pytest.mark.parametrize("camera_keys", ["z", "g t Z", "g x y"], ids=["flight", "analysis approach", "analysis orbit"])
@pytest.mark.parametrize("projection", ["", "p"], ids=["perspective", "parallel"])
def test_u_past_a_key_move_of_the_camera_gives_each_zoom_back_with_its_step(
        tmp_path: Path, projection: str, camera_keys: str) -> None:
    """Wheel notches and `.` zoomed the parallel view, then a key moved the camera: `u` took the key's
    move back, then the zooms' steps with their matrices but not their sizes, so back at the start the
    view stayed as zoomed as the last zoom left it (and `g`'s turn, which pushes without ending the
    view's moves, took the last zoom's size back one step early)."""
    viewer = viewer_with(projection, (octahedron(tmp_path / "m.obj", 20.0),), empty=True)
    scene, host = viewer.scene, RecordingHost()
    states = [(scene.camera.model.copy(), scene.projection_matrix(1.0))]
    for notches in (1, 2):
        commands.dolly_view(scene, notches)
        commands.end_view_gesture(scene)
        states.append((scene.camera.model.copy(), scene.projection_matrix(1.0)))
    for key in parse_key_sequence(f". c {camera_keys}"):
        dispatch(scene, key, host)
        if key.token in (".", "g", "x", "y", "z", "Z"):
            states.append((scene.camera.model.copy(), scene.projection_matrix(1.0)))
    for model, projection_matrix in states[-2::-1]:
        dispatch(scene, parse_key_sequence("u")[0], host)
        assert np.array_equal(scene.camera.model, model)
        assert np.array_equal(scene.projection_matrix(1.0), projection_matrix)


def test_u_past_a_key_move_of_the_camera_draws_the_view_it_began_from(tmp_path: Path) -> None:
    model = (octahedron(tmp_path / "m.obj", 20.0),)
    start = picture(tmp_path, "p", model, name="start.png")
    assert np.array_equal(picture(tmp_path, "p . c z u u", model, name="undone.png"), start)


@pytest.mark.parametrize("keys", ["", "p"], ids=["perspective", "parallel"])
def test_the_wheel_backs_off_no_further_than_the_view_can_draw(tmp_path: Path, keys: str) -> None:
    """1,200 notches out took the camera to 1e57 (a parallel view's half height to 1e111): each frame
    printed numpy's 'overflow encountered in cast', and the next API call refused the half height. It
    stops at DOLLY_FARTHEST times the object's size, where the object is a speck, and comes back in."""
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.load(octahedron(tmp_path / "m.obj", 100.0)).press(keys)
        scene = viewer.scene
        size = float(np.linalg.norm(np.ptp(scene.object.mesh.bounds, axis=0)))
        for _ in range(1200):
            commands.dolly_view(scene, -1)
        reach = scene.modes.parallel_half_height if keys else np.linalg.norm(scene.camera.origin - scene.object.centre)
        assert reach == pytest.approx(commands.DOLLY_FARTHEST * size)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            viewer.render()
        commands.dolly_view(scene, 1)
        back = scene.modes.parallel_half_height if keys else np.linalg.norm(scene.camera.origin - scene.object.centre)
        assert back == pytest.approx(reach * commands.DOLLY_PER_NOTCH)


@pytest.mark.parametrize("point", [False, True], ids=["no object", "a model of one point"])
def test_the_wheel_backs_off_again_where_the_view_has_no_size(tmp_path: Path, point: bool) -> None:
    """With no object (--empty) or one of a single point, the view's size is 0, so DOLLY_FARTHEST times
    it was 0 too: notches in came nearer, and notches out then never moved the camera back."""
    if point:
        (tmp_path / "dot.obj").write_text("v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n")
    scene = viewer_with("", (tmp_path / "dot.obj",) if point else (), empty=True).scene
    start = scene.camera.origin.copy()
    for steps in (1, 1, 1, -1, -1, -1):
        commands.dolly_view(scene, steps)
    assert np.allclose(scene.camera.origin, start)


@pytest.mark.parametrize("size, steps", [(1e17, -1), (1e-17, 1)], ids=["out", "in"])
def test_the_parallel_wheel_stays_within_the_half_heights_a_call_takes(size: float, steps: int) -> None:
    """The largest and smallest models that may be drawn, zoomed out or in as far as the wheel goes:
    every call after must take the half height the wheel set (a model scaled by hand past them took it
    to 1.4e33; such a placing is now refused itself)."""
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.add_mesh(np.eye(3) * size, [[0, 1, 2]])
        viewer.press("p")
        for _ in range(1000):
            commands.dolly_view(viewer.scene, steps)
        assert HALF_HEIGHT_RANGE[0] <= viewer.scene.modes.parallel_half_height <= HALF_HEIGHT_RANGE[1]
        assert viewer.status.startswith("target objects")


def test_the_wheel_stops_where_the_near_plane_leaves_what_it_looks_at(tmp_path: Path) -> None:
    """A 10 km ground seen from above: stopped a thousandth of its size from its centre, as far as the
    near plane inside its box, the camera showed the ground beyond that point only, and half the
    picture was background."""
    ground = tmp_path / "ground.obj"
    ground.write_text("v -5000 0 -5000\nv -5000 0 5000\nv 5000 0 5000\nv 5000 0 -5000\nf 1 2 3 4\n")
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.load(ground)
        for _ in range(300):
            commands.dolly_view(viewer.scene, 1)
        pixels = np.asarray(viewer.render().convert("RGB")).astype(int)
    assert (pixels[SIZE[1] // 2:] != BACKGROUND).any(axis=2).all()  # the ground below the view's centre


def test_in_parallel_projection_the_wheel_zooms_in_no_further_than_it_comes_back_from(tmp_path: Path) -> None:
    """900 notches in made the view's half height 1.5e-39, past a 32-bit number's reach: the picture
    went blank, and 100 notches out left it 5.5e-35."""
    model = octahedron(tmp_path / "m.obj", 100.0, (5000.0, -3000.0, 12000.0))
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.load(model)
        viewer.press("p")
        half_height = viewer.scene.modes.parallel_half_height
        for _ in range(900):
            commands.dolly_view(viewer.scene, 1)
        pixels = np.asarray(viewer.render().convert("RGB")).astype(int)
        assert (pixels != BACKGROUND).any(axis=2).all(), "the view inside the model, filled by it"
        for _ in range(100):
            commands.dolly_view(viewer.scene, -1)
        assert viewer.scene.modes.parallel_half_height > half_height


def test_u_after_p_sizes_the_parallel_view_for_the_camera_it_gives_back(tmp_path: Path) -> None:
    """A view move made in perspective kept the half height of then, the default 150 that was never
    on screen: a 2-unit model shrank to a speck."""
    scene = viewer_with("HOME p u", (octahedron(tmp_path / "m.obj", 1.0),), empty=True).scene
    assert scene.modes.parallel_half_height == pytest.approx(scene.matching_parallel_half_height())
    assert scene.modes.parallel_half_height < 5.0


def test_in_parallel_projection_a_zoom_leaves_the_far_plane_where_it_is(tmp_path: Path) -> None:
    """It followed the boxes in view: one leaving the view on a wheel notch moved it from 682 to 82,
    and the depth view's grey with it."""
    front = octahedron(tmp_path / "front.obj", 10.0)
    back = octahedron(tmp_path / "back.obj", 10.0, (60.0, 0.0, -300.0))
    scene = viewer_with("p", (front, back), empty=True).scene
    scene.selected_object = 0
    far = scene.far_plane()
    for _ in range(30):
        commands.dolly_view(scene, 1)
        assert scene.far_plane() == far


def test_looking_through_an_object_the_view_moves_say_so_and_leave_the_camera(tmp_path: Path) -> None:
    """The wheel, a drag, `.` and HOME moved the hidden camera: nothing on screen changed, and `C` again
    showed it somewhere else."""
    viewer = viewer_with("C")
    scene = viewer.scene
    start = scene.camera.model.copy()
    commands.dolly_view(scene, 5)
    commands.orbit_view(scene, 100, 20, SIZE)
    for key in (".", "HOME"):
        viewer.press(parse_key_sequence(key)[0])
    assert np.array_equal(scene.camera.model, start) and "C looks through the camera again" in scene.message


def test_a_window_wider_than_three_to_one_keeps_the_near_plane_clear_of_what_it_shows(tmp_path: Path) -> None:
    """A 2-unit box at the right edge of a 1000x200 window, 3 units from the eye: the near plane kept
    clear of a 3:1 view's boxes only, and cut it away whole."""
    side = octahedron(tmp_path / "side.obj", 1.0, (14.0, 0.0, 147.0))
    scene = viewer_with("", (side,)).scene
    wide = picture(tmp_path, "", (side,), empty=False, name="wide.png", size=(1000, 200))
    assert scene.near_plane(5.0) < nearest_depth(scene, scene.objects[-1])
    assert ((wide[..., 0] > 40) & (wide[..., 2] < 150)).any(), "the box shows at the right"


def test_a_gesture_is_one_undo_step_and_u_takes_it_back_whatever_is_targeted(tmp_path: Path) -> None:
    scene = scene_with_model(tmp_path)
    start, history = scene.camera.model.copy(), len(scene.camera.history)
    for _ in range(50):
        commands.orbit_view(scene, 3, 1, SIZE)
    commands.end_view_gesture(scene)  # the button released
    for _ in range(20):
        commands.dolly_view(scene, 1)
    assert len(scene.camera.history) == history + 2
    commands.undo(scene, RecordingHost())  # objects are targeted, and still the view goes back
    commands.undo(scene, RecordingHost())
    assert np.array_equal(scene.camera.model, start)
    commands.undo(scene, RecordingHost())
    assert scene.message == "nothing to undo"  # the object never moved


def test_a_move_of_the_target_makes_u_undo_that_move_not_the_view(tmp_path: Path) -> None:
    scene = scene_with_model(tmp_path)
    commands.orbit_view(scene, 30, 0, SIZE)
    host = RecordingHost()
    for key in parse_key_sequence("x u"):
        dispatch(scene, key, host)
    assert len(scene.object.history) == 1 and len(scene.camera.history) == 2


@pytest.mark.parametrize("models", [1, 0], ids=["the sun moved along x", "no object to move"])
def test_a_refused_move_of_the_target_leaves_u_to_undo_the_view(tmp_path: Path, models: int) -> None:
    """A drag turned the view, then a key the target refused (the sun has no place to move; --empty has
    no object) said so and moved nothing, yet `u` said 'nothing to undo' and left the view turned."""
    keys = "c c t" if models else ""
    viewer = viewer_with(keys, (octahedron(tmp_path / "m.obj", 20.0),)[:models], empty=True)
    scene, host = viewer.scene, RecordingHost()
    start = scene.camera.model.copy()
    commands.orbit_view(scene, 30, 0, SIZE)
    turned = scene.camera.model.copy()
    dispatch(scene, parse_key_sequence("x")[0], host)
    assert np.array_equal(scene.camera.model, turned) and scene.message  # refused, and said
    dispatch(scene, parse_key_sequence("u")[0], host)
    assert np.array_equal(scene.camera.model, start) and scene.message == ""


def test_a_ctrl_drag_going_on_as_a_load_joins_is_one_undo_step_of_the_new_model(tmp_path: Path) -> None:
    """A load finishing mid ctrl-drag selects the new model, which the drag then turns: its events were
    folded at the depth of the model it began on, so `u` took the new one back an event at a time."""
    scene = scene_with_model(tmp_path)
    host = RecordingHost()
    for key in parse_key_sequence("x x x"):
        dispatch(scene, key, host)
    commands.drag(scene, 5, 0, SIZE)
    joined = load_model_object(octahedron(tmp_path / "joined.obj", 5.0, (30.0, 0.0, 0.0)))
    commands.add_loaded(scene, joined, as_camera=False)
    for _ in range(10):
        commands.drag(scene, 5, 3, SIZE)
    assert scene.object is joined and len(joined.history) == 2


def _camera_over_home_and_dot(v: marraztu.Viewer, over_them: str) -> list[tuple[np.ndarray, float]]:
    """t x, p sized by hand to 40, HOME and `.`, then a move of the camera that is not a view move over
    them; where the camera stood and the half height before each of those three moves, latest first."""
    scene, camera = v.scene, v.scene.camera
    v.press("t x p")
    scene.modes.parallel_half_height = 40.0  # apart from the sizes HOME and `.` set
    stages = [(camera.model.copy(), scene.modes.parallel_half_height)]
    for key in ("HOME", "."):
        v.press(key)
        stages.append((camera.model.copy(), scene.modes.parallel_half_height))
    if over_them == "by hand":
        moved = camera.model.copy()
        moved[0, 3] += 1.0
        camera.model = moved
    else:  # g turns the camera to another object: analysis mode's aim, neither a view move nor a target's
        v.press("TAB c g c c TAB TAB")
        assert scene.modes.camera_mode is marraztu.model.scene.CameraMode.ANALYSIS
    assert not np.array_equal(camera.model, stages[-1][0]) and scene.object is scene.objects[0]
    return stages[::-1]


@pytest.mark.parametrize("over_them", ["by hand", "g"])
def test_a_camera_move_over_the_views_moves_is_undone_first_and_strands_none(over_them: str) -> None:
    """p, HOME, `.`, then `cam.model = M` (or g's turn): u took M back using `.`'s turn, then `.`'s, and
    said 'nothing to undo' with HOME's move left on the camera (only `c u` reached it). Now u takes
    back M, `.` with its half height, HOME with its, then the object's move."""
    with marraztu.Viewer(size=(64, 64)) as v:
        scene, camera = v.scene, v.scene.camera
        stages = _camera_over_home_and_dot(v, over_them)
        v.press("u")  # the move over them: the half height stays `.`'s
        assert np.array_equal(camera.model, stages[0][0]) and scene.modes.parallel_half_height == stages[0][1]
        for (before, size_before), (after, _) in zip(stages[1:], stages):
            assert scene.view_moves and camera.made_by_view_move()
            v.press("u")
            assert np.array_equal(camera.model, before) and scene.modes.parallel_half_height == size_before
        assert len(camera.history) == 1 and not scene.view_moves and len(scene.objects[0].history) == 2
        v.press("u")
        assert len(scene.objects[0].history) == 1 and v.message == ""
        v.press("u")
        assert v.message == "nothing to undo"


def test_keys_that_frame_twice_and_aim_the_camera_then_undo_all_three_draw_the_start_picture(tmp_path: Path) -> None:
    """`.` on one ship, `.` on the next, g aimed at the third: the third u said 'nothing to undo' and
    the view stayed framed on the first ship; now it is the picture `p` alone draws."""
    keys = "p . TAB . TAB c g c c TAB u u u"
    start = picture(tmp_path, "p", empty=False, name="start.png")
    np.testing.assert_array_equal(picture(tmp_path, keys, empty=False, name="undone.png"), start)


def test_a_view_move_left_after_its_cameras_history_was_replaced_ends_at_its_start() -> None:
    """A history replaced by hand under pending view moves: u takes that history back a step a press
    and then passes those view moves over, on to the target's move; no press stalls or reads past it."""
    with marraztu.Viewer(size=(64, 64)) as v:
        scene, camera = v.scene, v.scene.camera
        v.press("t x HOME .")
        start = camera.history[0]
        camera.history = [start, start + 0.0, start + 0.0]  # view_sizes now name matrices no longer on it
        v.press("u u")
        assert len(camera.history) == 1 and len(scene.objects[0].history) == 2
        v.press("u")
        assert not scene.view_moves and len(scene.objects[0].history) == 1 and v.message == ""
        v.press("u")
        assert v.message == "nothing to undo"


def test_a_size_out_of_range_is_not_echoed_digit_by_digit() -> None:
    from marraztu.render.layout import parse_size

    with pytest.raises(ValueError, match="out of range") as caught:
        parse_size("9" * 4000 + "x9")
    assert len(str(caught.value)) < 120
    with pytest.raises(ValueError, match="size 0x10 is out of range"):
        parse_size("0x10")


def test_a_scene_file_that_places_no_camera_is_framed(tmp_path: Path) -> None:
    """Without [[cameras]] a scene file took the built-in camera, 150 units from a 1-unit cube, which
    showed as a few pixels and said nothing; it is framed as a model given alone is. One that places
    a camera keeps it."""
    octahedron(tmp_path / "m.obj", 1.0)
    entry = '[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n'
    camera = '[[cameras]]\nmodel = "m.obj"\nposition = [0, 0, 150]\n'
    (tmp_path / "alone.toml").write_text(entry)
    (tmp_path / "placed.toml").write_text(entry + camera)
    for name, rows in (("alone.toml", math.sin(math.atan(FILL)) * SIZE[1]), ("placed.toml", 2 * SIZE[1] / 300)):
        out = take_screenshot(StartOptions(scene_file=tmp_path / name), tmp_path / "shot.png", SIZE)
        assert covered_rows(np.asarray(Image.open(out).convert("RGB")).astype(int)) == pytest.approx(rows, abs=3)


# --- a model drawn black -------------------------------------------------------------------------
def _without_ambient(path: Path, ka: str = "0 0 0") -> Path:
    """An octahedron whose MTL has no ambient colour, as SketchUp and Maya write one."""
    octahedron(path, 10.0)
    path.with_suffix(".mtl").write_text(f"newmtl dark\nKa {ka}\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 50\n")
    path.write_text(f"mtllib {path.with_suffix('.mtl').name}\nusemtl dark\n" + path.read_text())
    return path


@pytest.mark.parametrize("keys", ["", "0"], ids=["lights off", "the sun on"])
def test_a_model_drawn_black_as_it_is_loaded_says_why(tmp_path: Path, keys: str) -> None:
    """--empty a model of Ka 0 0 0 drew a black shape under SPEC's ambient light alone, and its message
    said nothing of why."""
    model = _without_ambient(tmp_path / "dark.obj")
    viewer = viewer_with(keys, empty=True)
    viewer.press(parse_key_sequence(f"f={model}")[0])
    assert viewer.scene.message.endswith(DARK_HINT) == (keys == ""), viewer.scene.message
    pixels = picture(tmp_path, keys, (model,))
    shown = pixels[(pixels != BACKGROUND).any(axis=2)]
    assert (shown.max() == 0) == (keys == "")  # the hint says what the picture shows
    started = viewer_with("", (model, _without_ambient(tmp_path / "lit.obj", "0.2 0.2 0.2")), empty=True)
    loads = [line for line in started.scene.message.splitlines() if line.startswith("loaded")]
    assert [line.endswith(DARK_HINT) for line in loads] == [True, False], loads
    stepped = viewer_with(keys, (tmp_path / "lit.obj",), empty=True)  # PageDown from lit.obj reaches dark.obj
    stepped.press(parse_key_sequence("PAGEDOWN")[0])
    assert stepped.scene.message.startswith("dark.obj in place of lit: ")
    assert stepped.scene.message.endswith(DARK_HINT) == (keys == ""), stepped.scene.message


def test_a_mesh_added_from_python_around_the_camera_says_so() -> None:
    """add_mesh joins as a load does, and its message said where the view shows it, but not that a
    room made round the camera (0 0 150) shows only its inside."""
    import marraztu

    corners = np.array([[x, y, z] for x in (-10.0, 10.0) for y in (-10.0, 10.0) for z in (140.0, 160.0)])
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    with marraztu.Viewer(size=(64, 64)) as viewer:
        viewer.add_mesh(corners, quads, name="room")
        assert viewer.message.startswith("added room: ") and AROUND_WORDS in viewer.message, viewer.message
        viewer.add_mesh(corners - [0.0, 0.0, 100.0], quads, name="ahead")
        assert AROUND_WORDS not in viewer.message, viewer.message



@pytest.mark.parametrize("lines", [False, True], ids=["filled", "lines"])
def test_a_key_that_leaves_a_model_thinner_than_a_pixel_says_so_once(tmp_path: Path, lines: bool) -> None:
    """A 100:1 beam moved away by t Z, its outline under a pixel thick at the 13th press, vanished from
    the filled picture without a word, where a load or `.` leaving it so said it was thinner than a pixel;
    lines light pixels however thin, and say nothing."""
    beam = box(tmp_path / "beam.obj", (100.0, 1.0, 1.0))
    with marraztu.Viewer(size=(400, 300), empty=True) as viewer:
        viewer.load(beam).press("t l" if lines else "t")
        said, lit = [], []
        for _ in range(16):
            said.append(viewer.press("Z").message)
            lit.append(int((np.asarray(viewer.render())[..., :3] != BACKGROUND).any(axis=2).sum()))
    if lines:
        assert set(said) == {""} and min(lit) > 0
    else:
        gone = lit.index(0)
        assert said == [""] * gone + [f"beam is now {THIN_WORDS}"] + [""] * (len(said) - gone - 1), (said, lit)
        assert 0 < gone < len(said) - 1 and set(lit[gone:]) == {0}, lit


def test_a_mouse_move_that_leaves_a_model_thinner_than_a_pixel_says_so_whatever_the_message_said_of_others(
        tmp_path: Path) -> None:
    """The start's message said another model was thinner than a pixel: the wheel, which says nothing of its
    own, then left the selected model so without a word, taking those words for its own."""
    beam = box(tmp_path / "beam.obj", (1000.0, 1.0, 1.0), (0.0, 300.0, 0.0))
    cube = box(tmp_path / "cube.obj", (10.0, 10.0, 10.0))
    viewer = Viewer(empty_scene(), NoFrontend(), frame_size=lambda: (400, 300))
    viewer.start(StartOptions(empty=True, models=(beam, cube)), longest_texture_side=64)
    scene, aspect = viewer.scene, viewer.narrowest_aspect()
    assert scene.object.name == "cube" and scene.message.endswith(f"beam: {THIN_WORDS}"), scene.message
    for _ in range(100):  # the wheel backs away a notch at a time
        viewer.move_by_mouse(lambda moved: commands.dolly_view(moved, -1))
        if scene.sight(scene.object, aspect, 300) is not Sight.SEEN:
            break
    assert scene.sight(scene.object, aspect, 300) is Sight.THIN and scene.message == f"cube is now {THIN_WORDS}"
