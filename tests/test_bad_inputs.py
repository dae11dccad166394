"""Bad files through every door (SPEC 7): the `f` key, the command line, `--keys f=`, `--scene`,
`--texture`. A bad file never crashes, never changes the scene, never leaves GL objects behind, and is
told in one line naming the file (and the line); a size a file merely claims is never allocated.

The inputs come from tests/corpus.py.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
import textwrap
import tracemalloc
from collections import Counter
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from marraztu.cli import main as cli_main
from marraztu.control.keymap import KeyPress
from marraztu.control.viewer import BackgroundLoader, StartOptions, Viewer
from marraztu.errors import LoadError
from marraztu.loaders.images import fallback_texture, load_image
from marraztu.loaders.obj import load_obj
from marraztu.loaders.scenefile import load_builtin_scene, load_scene
from marraztu.model.scene import Scene, Target
from marraztu.render.renderer import Renderer
from support import corpus
from support.corpus import Case
from support.scenes import RenderingViewer

ROOT = Path(__file__).resolve().parents[1]
SMALL_GROWTH_BYTES = 50 * corpus.MEGABYTE
# Only against a hang: how fast a load is belongs to the bench, whose shapes section has these inputs.
HANG_TIMEOUT = 600.0

def params(cases: list[Case]) -> list:
    """pytest params with readable ids; root skips chmod 000 (it reads every file)."""
    out = []
    for case in cases:
        marks = []
        if case.setup == "unreadable" and corpus.running_as_root():
            marks.append(pytest.mark.skip(reason="running as root: chmod 000 does not stop reading"))
        out.append(pytest.param(case, id=case.id, marks=marks))
    return out


BAD_OBJ = corpus.bad_obj_cases()
GOOD_OBJ = corpus.good_obj_cases()
BAD_IMAGES = corpus.bad_image_cases()
GOOD_IMAGES = corpus.good_image_cases()
BAD_SCENES = corpus.bad_scene_cases()


@pytest.fixture(scope="module")
def corpus_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("corpus")


@pytest.fixture(scope="module")
def case_path(corpus_dir: Path) -> Callable[[Case], Path]:
    written: dict[str, Path] = {}

    def path(case: Case) -> Path:
        key = f"{case.kind}:{case.id}"
        if key not in written:
            written[key] = corpus.write_case(case, corpus_dir)
        return written[key]

    yield path
    for written_path in written.values():  # let pytest's clean-up delete what chmod 000 locked
        if written_path.exists() and not written_path.is_symlink():
            written_path.chmod(0o755 if written_path.is_dir() else 0o644)


def assert_names(message: str, case: Case, path: Path) -> None:
    """The message names the file, and its line where the case has one."""
    assert str(path) in message, message
    if case.line is not None:
        assert f"{path}:{case.line}:" in message, f"line {case.line} not named: {message}"


# --------------------------------------------------------------------------------------------------
# The scene is exactly as before
# --------------------------------------------------------------------------------------------------
@dataclass
class SceneState:
    """Everything a failed load must leave alone, copied out of a scene."""

    objects: list[int]
    cameras: list[int]
    selection: tuple[int, int, int]
    faces: list[int]
    histories: list[list[np.ndarray]]
    modes: str
    lights: list[tuple]

    @classmethod
    def of(cls, scene: Scene) -> SceneState:
        everything = scene.objects + scene.cameras
        return cls(
            objects=[id(obj) for obj in scene.objects],
            cameras=[id(obj) for obj in scene.cameras],
            selection=(scene.selected_object, scene.selected_camera, scene.selected_light),
            faces=[obj.selected_face for obj in everything],
            histories=[[matrix.copy() for matrix in obj.history] for obj in everything],
            modes=repr(scene.modes),
            lights=[(light.on, light.aperture_deg, light.position.tobytes(), light.direction.tobytes(),
                     light.axis_in_owner.tobytes(), len(light.history)) for light in scene.lights],
        )

    def assert_same(self, other: SceneState) -> None:
        assert other.objects == self.objects
        assert other.cameras == self.cameras
        assert other.selection == self.selection
        assert other.faces == self.faces
        assert other.modes == self.modes
        assert other.lights == self.lights
        assert [len(h) for h in other.histories] == [len(h) for h in self.histories]
        for before, after in zip(self.histories, other.histories):
            for old, new in zip(before, after):
                assert np.array_equal(old, new)


class RecordingFrontend:
    def __init__(self) -> None:
        self.calls: list[str] = []

    def quit(self) -> None:
        self.calls.append("quit")

    def save_screenshot(self) -> None:
        self.calls.append("save_screenshot")

    def notice(self, text: str) -> None:
        self.calls.append(("notice", text))


@pytest.fixture(scope="module")
def viewer(own_ctx) -> Iterator[Viewer]:
    """SPEC 3's scene, moved about a little so histories and selections are not all trivial.

    GL objects Python drops without releasing are counted over the whole module: none may be."""
    corpus.make_current(own_ctx)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        renderer = Renderer(own_ctx)
        scene = load_builtin_scene()
        view = RenderingViewer(scene, renderer, RecordingFrontend())
        scene.texture = fallback_texture()
        view.press_sequence("TAB x x t y g Z ENTER ENTER c x r y c c")  # ends targeting objects
        assert scene.modes.target is Target.OBJECTS
        corpus.render_float(own_ctx, renderer, scene)
        yield view
    corpus.make_current(own_ctx)  # the release must reach the context that made these objects
    renderer.release()
    assert dropped.leaked == 0, "GL objects were dropped without release"


@pytest.fixture(scope="module")
def census(viewer: Viewer, own_ctx) -> Counter[str]:
    """The live GL objects of the module's viewer, by type: what every test must leave behind."""
    return corpus.live_gl_objects(own_ctx)


def failed_load_leaves_everything(viewer: Viewer, own_ctx, census: Counter[str],
                                  load: Callable[[], object]) -> str:
    """Runs `load`, checks scene, GL objects and rendering are as before; returns the message."""
    scene = viewer.scene
    before = SceneState.of(scene)
    load()
    SceneState.of(scene).assert_same(before)
    corpus.assert_sane_pixels(corpus.render_float(own_ctx, viewer.renderer, scene))
    assert corpus.live_gl_objects(own_ctx) == census
    return scene.message


@pytest.mark.parametrize("case", params(BAD_OBJ))
def test_bad_obj_through_the_f_key_leaves_the_scene_as_it_was(case: Case, case_path, viewer, own_ctx,
                                                              census) -> None:
    path = case_path(case)
    press = KeyPress("f", str(path))
    message = failed_load_leaves_everything(viewer, own_ctx, census, lambda: viewer.press(press))
    assert_names(message, case, path)


@pytest.fixture(scope="module")
def window_viewer(viewer: Viewer) -> Iterator[Viewer]:
    """The module's scene and renderer behind the window's kind of viewer: loads on a worker thread."""
    loader = BackgroundLoader()
    yield RenderingViewer(viewer.scene, viewer.renderer, RecordingFrontend(), background=loader)
    loader.shutdown()


def finish_background_loads(window_viewer: Viewer) -> None:
    """What the window's frames do: wait for the worker, then let finished loads join the scene."""
    for job in window_viewer.background.uncollected():
        job.future.exception(timeout=HANG_TIMEOUT)  # waits for the job, failed or not
    window_viewer.collect_loads()


@pytest.mark.parametrize("case", params(BAD_OBJ))
def test_bad_obj_through_the_window_worker_leaves_the_scene_as_it_was(case: Case, case_path, window_viewer,
                                                                      own_ctx, census) -> None:
    """The window loads `f` and dropped files on a worker thread; a failure joins nothing."""
    path = case_path(case)

    def load_and_collect() -> None:
        window_viewer.press(KeyPress("f", str(path)))
        finish_background_loads(window_viewer)

    message = failed_load_leaves_everything(window_viewer, own_ctx, census, load_and_collect)
    assert_names(message, case, path)


def test_odd_named_obj_through_the_window_worker_joins_the_scene(case_path, window_viewer, own_ctx,
                                                                census) -> None:
    case = next(case for case in GOOD_OBJ if case.id == "spaces_and_non_ascii_name")
    scene = window_viewer.scene
    count = len(scene.objects)
    window_viewer.press(KeyPress("f", str(case_path(case))))
    finish_background_loads(window_viewer)
    assert len(scene.objects) == count + 1 and scene.selected_object == count, scene.message
    corpus.assert_sane_pixels(corpus.render_float(own_ctx, window_viewer.renderer, scene))
    window_viewer.press(KeyPress("DELETE"))
    corpus.render_float(own_ctx, window_viewer.renderer, scene)
    assert corpus.live_gl_objects(own_ctx) == census


# A cross-section of the OBJ corpus, for the doors that reach the same loader a second way.
OBJ_SAMPLE = ("empty", "binary_noise", "truncated_mid_face", "index_zero", "index_past_end",
              "negative_past_start", "face_of_two_vertices", "nan_coordinate", "missing", "directory",
              "index_absurd", "bad_in_odd_name", "spaces_and_non_ascii_name")


@pytest.mark.parametrize("case", params([case for case in BAD_OBJ if case.id in OBJ_SAMPLE]))
def test_bad_obj_as_a_new_camera_leaves_the_scene_as_it_was(case: Case, case_path, viewer, own_ctx,
                                                            census) -> None:
    """Target cameras: the same file would have become a camera; nothing changes either."""
    path = case_path(case)
    scene = viewer.scene
    scene.modes.target = Target.CAMERAS
    try:
        message = failed_load_leaves_everything(viewer, own_ctx, census, lambda: viewer.load_model(path))
    finally:
        scene.modes.target = Target.OBJECTS
    assert_names(message, case, path)


@pytest.mark.parametrize("case", params(GOOD_OBJ))
def test_odd_but_valid_obj_loads_adds_one_selected_object(case: Case, case_path, viewer, own_ctx, census) -> None:
    path = case_path(case)
    scene = viewer.scene
    count = len(scene.objects)
    assert viewer.load_model(path) is True, scene.message
    assert len(scene.objects) == count + 1 and scene.selected_object == count
    assert path.name in scene.message
    corpus.assert_sane_pixels(corpus.render_float(own_ctx, viewer.renderer, scene))
    viewer.press(KeyPress("DELETE"))  # leave the module's scene as other tests expect it
    assert len(scene.objects) == count
    corpus.render_float(own_ctx, viewer.renderer, scene)
    assert corpus.live_gl_objects(own_ctx) == census, "DELETE kept GL objects"


@pytest.mark.parametrize("case", params(BAD_OBJ))
def test_bad_obj_raises_load_error_naming_file_and_line(case: Case, case_path) -> None:
    path = case_path(case)
    with pytest.raises(LoadError) as caught:
        load_obj(path)
    assert_names(str(caught.value), case, path)
    assert caught.value.path == str(path)
    if case.line is not None:
        assert caught.value.line == case.line


@pytest.mark.parametrize("case", params(BAD_IMAGES))
def test_bad_texture_gives_the_fallback_and_a_message(case: Case, case_path, viewer, own_ctx, census) -> None:
    """The window's texture path: a message naming the file, the built-in checker, the scene untouched."""
    path = case_path(case)
    with pytest.raises(LoadError) as caught:
        load_image(path)
    assert_names(str(caught.value), case, path)
    before = SceneState.of(viewer.scene)
    viewer.start(StartOptions(texture=path), longest_texture_side=4096)
    message = viewer.scene.message
    assert str(path) in message and viewer.frontend.calls[-1] == ("notice", message)
    np.testing.assert_array_equal(viewer.scene.texture, fallback_texture())
    SceneState.of(viewer.scene).assert_same(before)
    corpus.assert_sane_pixels(corpus.render_float(own_ctx, viewer.renderer, viewer.scene))
    assert corpus.live_gl_objects(own_ctx) == census, "the old texture was not released"


@pytest.mark.parametrize("case, shape", [pytest.param(case, shape, id=case.id) for case, shape in GOOD_IMAGES])
def test_valid_images_with_odd_headers_load(case: Case, shape: tuple[int, int], case_path) -> None:
    image = load_image(case_path(case))
    assert image.shape == (*shape, 3) and image.dtype == np.uint8


def test_valid_ppm_pixels_are_read_exactly(case_path) -> None:
    """Comments in the header, '#' and newlines inside binary pixel data: the pixels still come out."""
    by_id = {case.id: case for case, _ in GOOD_IMAGES}
    expected = np.frombuffer(corpus.VALID_P6[-36:], np.uint8).reshape(3, 4, 3)
    assert np.array_equal(load_image(case_path(by_id["p6"])), expected)
    assert np.array_equal(load_image(case_path(by_id["p6_comments_in_odd_places"])), expected)
    p3 = load_image(case_path(by_id["p3_comments_between_samples"]))
    assert p3.tolist() == [[[255, 0, 0], [0, 0, 255]]]
    assert load_image(case_path(by_id["p3_maxval_1"])).tolist() == [[[255, 0, 255], [0, 255, 0]]]


@pytest.mark.parametrize("case", params(BAD_SCENES))
def test_bad_scene_file_raises_load_error_naming_file_and_line(case: Case, case_path) -> None:
    path = case_path(case)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert_names(str(caught.value), case, path)


# --------------------------------------------------------------------------------------------------
# The screenshot command: one line on stderr, no traceback, non-zero exit
# --------------------------------------------------------------------------------------------------
DOORS_OF_KIND = {"obj": ("positional", "keys"), "image": ("texture",), "scene": ("scene",)}


def screenshot_args(door: str, path: Path, out: Path) -> list[str]:
    common = ["screenshot", "-o", str(out), "--size", "16x16"]
    if door == "positional":
        return [*common, "--empty", str(path)]
    if door == "keys":
        return [*common, "--empty", "--keys", shlex.quote(f"f={path}")]
    if door == "scene":
        return [*common, "--scene", str(path)]
    return [*common, "--empty", "--texture", str(path)]


@dataclass(frozen=True)
class Run:
    returncode: int
    stderr: str
    output_written: bool


def run_in_process(argv: list[str], capsys: pytest.CaptureFixture[str], out: Path) -> Run:
    """`python -m marraztu ARGS` minus the interpreter start: marraztu.cli.main is all `__main__` runs. An
    exception other than the one-line error escapes here and fails the test with its traceback.

    The command makes and releases a GL context of its own; the one current before is again after."""
    with corpus.kept_gl_context():
        returncode = cli_main(argv)
    return Run(returncode, capsys.readouterr().err, out.exists())


def run_subprocess(argv: list[str], out: Path) -> Run:
    env = {**os.environ, "PYTHONIOENCODING": "utf-8"}
    done = subprocess.run([sys.executable, "-m", "marraztu", *argv], cwd=ROOT, capture_output=True,
                          timeout=120, env=env)
    return Run(done.returncode, done.stderr.decode("utf-8", "replace"), out.exists())


def assert_one_line_error(run: Run, case: Case, path: Path) -> None:
    assert run.returncode != 0, run.stderr
    assert "Traceback" not in run.stderr, run.stderr
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, run.stderr
    assert_names(lines[0], case, path)
    assert not run.output_written


def door_params(cases: list[Case]) -> list:
    """Each case through its kind's first door, and the sample in OBJ_SAMPLE through every door:
    `f=PATH` reaches the same loader as a positional file, and each run starts a GL context and
    compiles the shaders, so a sample shows the quoting works."""
    def doors(case: Case) -> tuple[str, ...]:
        every = DOORS_OF_KIND[case.kind]
        return every if case.id in OBJ_SAMPLE else every[:1]

    return [pytest.param(door, case, id=f"{door}-{case.id}", marks=param.marks)
            for param in params(cases) for case in param.values for door in doors(case)]


@pytest.mark.parametrize("door, case", door_params(BAD_OBJ + BAD_IMAGES + BAD_SCENES))
def test_screenshot_refuses_bad_file_in_one_line(door: str, case: Case, case_path, tmp_path: Path,
                                                capsys, own_ctx) -> None:
    out = tmp_path / "x.png"
    run = run_in_process(screenshot_args(door, case_path(case), out), capsys, out)
    assert_one_line_error(run, case, case_path(case))


def test_texture_error_names_the_file_once_and_promises_no_fallback(case_path, tmp_path: Path, capsys,
                                                                    own_ctx) -> None:
    case = next(case for case in BAD_IMAGES if case.id == "truncated_p6_data")
    path, out = case_path(case), tmp_path / "x.png"
    run = run_in_process(screenshot_args("texture", path, out), capsys, out)
    assert run.returncode != 0
    assert run.stderr.count(str(path)) == 1 and "built-in" not in run.stderr, run.stderr


# A few of each kind through a real `python -m marraztu` process: interpreter start, stderr encoding of
# non-ASCII names, exit status. (kind, id) -> doors. Run side by side: each costs an interpreter start.
SUBPROCESS_BAD_SAMPLE = {
    ("obj", "empty"): ("positional",),
    ("obj", "binary_noise"): ("positional",),
    ("obj", "index_past_end"): ("positional", "keys"),
    ("obj", "nan_coordinate"): ("keys",),
    ("obj", "missing"): ("positional",),
    ("obj", "bad_in_odd_name"): ("positional", "keys"),
    ("image", "absurd_size"): ("texture",),
    ("image", "bad_in_odd_name"): ("texture",),
    ("scene", "syntax_error"): ("scene",),
    ("scene", "model_fails_to_load"): ("scene",),
    ("scene", "missing"): ("scene",),
}
SUBPROCESS_GOOD_SAMPLE = {
    ("obj", "spaces_and_non_ascii_name"): ("positional", "keys"),
    ("image", "spaces_and_non_ascii_name"): ("texture",),
}


def sampled_runs(cases: list[Case], wanted: dict[tuple[str, str], tuple[str, ...]]) -> list[tuple[str, Case]]:
    return [(door, case) for case in cases for door in wanted.get((case.kind, case.id), ())]


SUBPROCESS_BAD = sampled_runs(BAD_OBJ + BAD_IMAGES + BAD_SCENES, SUBPROCESS_BAD_SAMPLE)
SUBPROCESS_GOOD = sampled_runs(GOOD_OBJ + [case for case, _ in GOOD_IMAGES], SUBPROCESS_GOOD_SAMPLE)


class SubprocessRuns:
    """Starts every sampled screenshot process at once (a few at a time), hands results out by key."""

    def __init__(self, folder: Path, case_path: Callable[[Case], Path], workers: int = 3) -> None:
        self.pool = ThreadPoolExecutor(max_workers=workers)
        self.futures: dict[str, Future[Run]] = {}
        for door, case in SUBPROCESS_BAD + SUBPROCESS_GOOD:
            out = folder / f"{door}-{case.kind}-{case.id}.png"
            argv = screenshot_args(door, case_path(case), out)
            self.futures[self.key(door, case)] = self.pool.submit(run_subprocess, argv, out)

    @staticmethod
    def key(door: str, case: Case) -> str:
        return f"{door}:{case.kind}:{case.id}"

    def result(self, door: str, case: Case) -> Run:
        return self.futures[self.key(door, case)].result()


@pytest.fixture(scope="module")
def subprocess_runs(case_path, tmp_path_factory) -> Iterator[SubprocessRuns]:
    runs = SubprocessRuns(tmp_path_factory.mktemp("shots"), case_path)
    yield runs
    runs.pool.shutdown(wait=True)


@pytest.mark.parametrize("door, case", [pytest.param(door, case, id=f"{door}-{case.kind}-{case.id}")
                                        for door, case in SUBPROCESS_BAD])
def test_screenshot_process_refuses_bad_file_in_one_line(door: str, case: Case, case_path,
                                                         subprocess_runs) -> None:
    assert_one_line_error(subprocess_runs.result(door, case), case, case_path(case))


@pytest.mark.parametrize("door, case", [pytest.param(door, case, id=f"{door}-{case.kind}-{case.id}")
                                        for door, case in SUBPROCESS_GOOD])
def test_screenshot_process_accepts_odd_but_valid_file(door: str, case: Case, subprocess_runs) -> None:
    run = subprocess_runs.result(door, case)
    assert run.returncode == 0, run.stderr
    assert run.output_written


@pytest.mark.parametrize("door, case", door_params(GOOD_OBJ + [case for case, _ in GOOD_IMAGES]))
def test_screenshot_accepts_odd_but_valid_file(door: str, case: Case, case_path, tmp_path: Path,
                                               capsys, own_ctx) -> None:
    out = tmp_path / "x.png"
    run = run_in_process(screenshot_args(door, case_path(case), out), capsys, out)
    assert run.returncode == 0, run.stderr
    assert run.output_written


def test_scene_with_broken_texture_warns_in_one_line_and_still_renders(case_path, tmp_path: Path) -> None:
    """SPEC 7: a broken texture at start is a message and the fallback, not an exit."""
    case = corpus.scene_with_bad_texture()
    scene_path = case_path(case)
    out = tmp_path / "shot.png"
    done = subprocess.run([sys.executable, "-m", "marraztu", "screenshot", "-o", str(out), "--size", "16x16",
                           "--scene", str(scene_path)], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "broken.ppm" in lines[0], done.stderr
    assert out.exists()


# --------------------------------------------------------------------------------------------------
# Nothing is allocated in proportion to what a file merely claims
# --------------------------------------------------------------------------------------------------
# Corpus cases whose header or index claims far more than the file holds.
CLAIMS = {f"{case.kind}:{case.id}": case for case in BAD_OBJ + BAD_IMAGES if case.id in (
    "absurd_size", "absurd_size_p3", "largest_allowed_claim_p6", "png_absurd_size", "index_absurd",
    "index_far_past_end")}
LOADERS = {"image": load_image, "obj": load_obj}


@pytest.mark.parametrize("name", list(CLAIMS))
def test_claimed_size_is_not_allocated_traced(name: str, case_path) -> None:
    """tracemalloc sees Python's and numpy's allocations: the peak while loading stays small."""
    path = case_path(CLAIMS[name])
    loader = LOADERS[CLAIMS[name].kind]
    tracemalloc.start()
    try:
        with pytest.raises(LoadError):
            loader(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < SMALL_GROWTH_BYTES, f"{peak / corpus.MEGABYTE:.1f} MB traced while loading {name}"


PEAK_RSS_SCRIPT = textwrap.dedent("""
    import resource, sys
    from marraztu.errors import LoadError
    from marraztu.loaders.images import load_image
    from marraztu.loaders.obj import load_obj
    loader = load_image if sys.argv[1] == "image" else load_obj
    try:  # warm the code paths on a tiny valid file first, so imports do not count
        loader(sys.argv[3])
    except LoadError:
        pass
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    try:
        loader(sys.argv[2])
        outcome = "loaded"
    except LoadError:
        outcome = "LoadError"
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(outcome, (after - before) * 1024)  # ru_maxrss is in KiB on Linux
""")


def measure_peak_rss(kind: str, path: Path, warm_up: Path) -> tuple[str, int]:
    """(outcome, peak RSS growth in bytes) of loading `path` in a fresh interpreter."""
    done = subprocess.run([sys.executable, "-c", PEAK_RSS_SCRIPT, kind, str(path), str(warm_up)], cwd=ROOT,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    outcome, growth = done.stdout.split()
    return outcome, int(growth)


@pytest.fixture(scope="module")
def warm_up_files(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("warm")
    (folder / "ok.ppm").write_bytes(corpus.VALID_P6)
    (folder / "ok.obj").write_bytes(corpus.VALID_OBJ)
    return {"image": folder / "ok.ppm", "obj": folder / "ok.obj"}


@pytest.mark.parametrize("name", ["image:absurd_size", "image:png_absurd_size", "obj:index_absurd"])
def test_claimed_size_is_not_allocated_peak_rss(name: str, case_path, warm_up_files) -> None:
    """The process's peak resident memory (getrusage) while loading, in a fresh interpreter."""
    kind = CLAIMS[name].kind
    outcome, growth = measure_peak_rss(kind, case_path(CLAIMS[name]), warm_up_files[kind])
    assert outcome == "LoadError"
    assert growth < SMALL_GROWTH_BYTES, f"peak RSS grew {growth / corpus.MEGABYTE:.1f} MB loading {name}"


# --------------------------------------------------------------------------------------------------
# Paths that are not regular files: an endless device, a pipe nobody writes to
# --------------------------------------------------------------------------------------------------
_ADDRESS_SPACE_CAP = 1 << 30  # an endless read fails here instead of eating the machine


def _cap_address_space() -> None:
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (_ADDRESS_SPACE_CAP, _ADDRESS_SPACE_CAP))


LOADER_KINDS = [pytest.param("obj", id="obj"), pytest.param("image", id="image"),
                pytest.param("scene", id="scene")]
LOADER_SCRIPT = textwrap.dedent("""
    import resource, sys
    from marraztu.errors import LoadError
    from marraztu.loaders.images import load_image
    from marraztu.loaders.obj import load_obj
    from marraztu.loaders.scenefile import load_scene
    loader = {"obj": load_obj, "image": load_image, "scene": load_scene}[sys.argv[1]]
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    try:
        loader(sys.argv[2])
        print("loaded")
    except LoadError as error:
        print("LoadError", (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) * 1024, error)
""")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
@pytest.mark.parametrize("kind", LOADER_KINDS)
def test_endless_device_is_refused_without_reading_it(kind: str) -> None:
    """/dev/zero never ends: it must be refused, not read until memory runs out (a 1 GB address-space
    cap keeps a failing loader from eating the machine)."""
    done = subprocess.run([sys.executable, "-c", LOADER_SCRIPT, kind, "/dev/zero"], cwd=ROOT, capture_output=True,
                          text=True, timeout=60, preexec_fn=_cap_address_space)
    assert done.returncode == 0 and done.stdout.startswith("LoadError"), done.stdout + done.stderr[-500:]
    _, growth, message = done.stdout.split(maxsplit=2)
    assert int(growth) < SMALL_GROWTH_BYTES, growth
    assert "/dev/zero" in message


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
@pytest.mark.parametrize("kind", LOADER_KINDS)
def test_named_pipe_is_refused_without_blocking(kind: str, tmp_path: Path) -> None:
    """Opening a FIFO blocks until someone writes to it: a loader must look before it opens."""
    pipe = tmp_path / f"pipe.{ {'obj': 'obj', 'image': 'ppm', 'scene': 'toml'}[kind] }"
    os.mkfifo(pipe)
    process = subprocess.Popen([sys.executable, "-c", LOADER_SCRIPT, kind, str(pipe)], cwd=ROOT,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = process.communicate(timeout=5.0)  # imports take under a second; a refusal is at once
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        pytest.fail(f"{kind} loader blocked on a named pipe")
    assert out.startswith("LoadError") and str(pipe) in out, out + err


TOO_LARGE_WORDS = "cannot light the model"
TOO_SMALL_WORDS = "under 1e-18 the GPU's 32-bit numbers cannot light the model"


@pytest.mark.parametrize("size, words, edge", [
    ("1e20", TOO_LARGE_WORDS, "v 0 0 0\nv -1e18 0 0\nv 0 1e18 0\n"),
    ("3e38", TOO_LARGE_WORDS, "v 0 0 0\nv -1e18 0 0\nv 0 1e18 0\n"),
    ("1e-20", TOO_SMALL_WORDS, "v 0 0 0\nv 1e-18 0 0\nv 0 1e-18 0\n"),
    ("1e-300", TOO_SMALL_WORDS, "v 0 0 0\nv 1e-18 0 0\nv 0 1e-18 0\n"),
])
def test_a_model_too_large_or_too_small_to_light_is_refused_by_every_reader(tmp_path: Path, size: str, words: str,
                                                                            edge: str) -> None:
    """Past 1e18 a vector's squared length overflows the GPU's 32-bit numbers; under 1e-18 across, a
    framed model's vectors have squared lengths under float32's smallest normal number. Either way it
    was drawn flat red, or not at all, with numpy's overflow warnings on the terminal. The bounds
    themselves are drawn, and so is a model that is one point (no size at all)."""
    from marraztu.loaders.registry import load_model

    files = {"m.obj": f"v 0 0 0\nv {size} 0 0\nv 0 {size} 0\nf 1 2 3\n",
             "m.off": f"OFF\n3 1 0\n0 0 0\n{size} 0 0\n0 {size} 0\n3 0 1 2\n",
             "m.stl": f"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex {size} 0 0\n"
                      f"vertex 0 {size} 0\nendloop\nendfacet\nendsolid s\n"}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
        with pytest.raises(LoadError, match=words):
            load_model(tmp_path / name)
    (tmp_path / "edge.obj").write_text(edge + "f 1 2 3\n")
    assert load_model(tmp_path / "edge.obj").face_count == 1
    (tmp_path / "point.obj").write_text("v 5 5 5\nv 5 5 5\nv 5 5 5\nf 1 2 3\n")
    assert load_model(tmp_path / "point.obj").face_count == 1
