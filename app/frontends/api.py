"""The Python interface, for notebooks and scripts: the window's viewer, key map and renderer,
drawing offscreen (EGL, or the platform's default context) into pictures.

    import marraztu
    with marraztu.Viewer(size=(800, 600)) as v:
        v.load("model.obj")
        v.press("0 1 F x*5")
        v.render().save("picture.png")
"""

from __future__ import annotations

import atexit
import functools
import operator
import os
import threading
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from io import BytesIO
from pathlib import Path
from typing import Any, NoReturn, Sequence, TypeVar

import numpy as np
from PIL import Image

from marraztu.control.viewer import StartOptions, starting_scene
from marraztu.control.viewer import Viewer as KeyViewer
from marraztu.errors import KeyMapError, LoadError, ViewerError, escaped, shortened
from marraztu.frontends.heap import return_freed_memory
from marraztu.frontends.screenshot import OffscreenFrontend, picture_of, render_pixels
from marraztu.loaders.exchange import mesh_of_trimesh
from marraztu.loaders.images import load_image, picture_rgb
from marraztu.loaders.scenefile import give_part_materials, material_for_loaded
from marraztu.model.build import build_mesh, real_numbers
from marraztu.model.geometry import cannot_light, holds_in_float32
from marraztu.model.mesh import INDEX_LIMIT, counted
from marraztu.model.probe import probe as probe_scene
from marraztu.model.scene import Scene, SceneObject, kept_name, name_refusal
from marraztu.render.context import create_offscreen_context, refuse_forked_gl
from marraztu.render.layout import checked_size
from marraztu.render.renderer import Renderer
from marraztu.text.status import prompt_line, status_line

Size = tuple[int, int]
_Result = TypeVar("_Result")


@dataclass(frozen=True)
class LightShare:
    """One light's part of I at a vertex, in the seed's 0..255 units."""

    light: str
    reaches: bool  # False outside a spotlight's cone
    n_dot_l: float  # max(N.L, 0): a light behind the face adds nothing
    highlight: float  # max(N.H, 0)^ns
    diffuse: tuple[float, float, float]
    specular: tuple[float, float, float]
    to_light: tuple[float, float, float]  # L, world space, unit (zero outside a spotlight's cone)
    halfway: tuple[float, float, float]  # H = normalise(L + V)


@dataclass(frozen=True)
class ProbedVertex:
    """One vertex the renderer lights for the probed face, with every term of SPEC 4's I."""

    vertex: int  # 0-based row of the file's vertex table
    world_position: tuple[float, float, float]
    normal: tuple[float, float, float]  # world space: the face normal in Flat, the vertex normal in Gouraud
    n_dot_v: float
    ambient: tuple[float, float, float]  # Ka * Ia
    lights: tuple[LightShare, ...]
    total: tuple[float, float, float]  # I before the clamp, in the current term view
    colour: tuple[int, int, int]  # the 0..255 lit colour, before a texture or vertex colour tints it
    vertex_colour: tuple[int, int, int] | None  # the model's colour at the vertex, which multiplies it; None: none


@dataclass(frozen=True)
class ProbeReport:
    """The probe (key `i`) of the selected object's selected face, as numbers."""

    object: str
    face: int  # 0-based
    face_count: int
    material: str | None  # the file's name for the material the face is drawn with; None: none, or another
    shading: str
    view: str  # what the lit colour shows (key v): "everything", one term, one light, depth or normals
    back_face: bool
    culled: bool
    textured: bool  # a picture multiplies the pixel: it is a vertex's colour times the texel (T turns it off)
    vertices: tuple[ProbedVertex, ...]


def _triple(values: Any) -> tuple[float, float, float]:
    return tuple(float(v) for v in np.asarray(values, float).reshape(3))  # type: ignore[return-value]


def _checked_size(size: Sequence[int]) -> Size:
    """(width, height): a tuple, list or array of two whole numbers (a bool, a float or a text is no
    side), each in checked_size's range."""
    try:
        if not isinstance(size, (tuple, list, np.ndarray)):
            raise TypeError
        sides = tuple(size)
        if len(sides) != 2 or any(isinstance(side, (bool, np.bool_, str, bytes)) for side in sides):
            raise TypeError
        width, height = (operator.index(side) for side in sides)
    except (TypeError, ValueError):
        said = shortened(escaped(repr(size)))
        raise ValueError(f"size must be (width, height) in whole numbers, not {said}") from None
    return checked_size(width, height)


def _fixed(size: Size) -> Callable[[], Size]:
    """The size as the viewer asks for it; a function of the size alone, not of the Viewer."""
    return lambda: size


def _checked_flag(value: Any, what: str, none: bool = False) -> None:
    """Every switch of the interface takes True or False (numpy's too) and nothing else: "no" and 1
    are refused, not taken as true. `none`: None means "let the program decide"."""
    if not (isinstance(value, (bool, np.bool_)) or (none and value is None)):
        allowed = "True, False or None" if none else "True or False"
        raise ValueError(f"{what} is {allowed}, not {shortened(escaped(repr(value)))}")


def _checked_name(name: Any) -> None:
    """A name is text with words in it, or None for the default: str() of anything else would be a guess
    (b"abc" shown as "b'abc'"), and a scene file refuses an empty one too."""
    if name is None:
        return
    if not isinstance(name, str):
        raise TypeError(f"name is a str, not {type(name).__name__}")
    if not name.strip():
        raise ValueError("name is empty: give one with words in it, or None for the default")
    kept = escaped(name)  # as the scene keeps it: a line break written \n, as the status line shows it
    refusal = name_refusal(kept)
    if refusal is not None:
        raise ValueError(refusal if kept == name else f"{refusal} (its control characters escaped, as it is kept)")


def _checked_path(path: Any, what: str) -> Path:
    """A file name given as a str or a path (os.PathLike); TypeError naming the argument otherwise."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{what} is a file name (str or Path), not {type(path).__name__}")
    return Path(path)


def _release(ctx: Any, renderer: Renderer) -> None:
    """The renderer's objects; the context is kept for the next Viewer where fewer than the most are kept."""
    with ctx:  # its objects are released in their own context, whichever Viewer drew last
        renderer.release()
    if len(_spare_contexts) >= MAX_SPARE_CONTEXTS:
        ctx.release()
    else:
        _spare_contexts.append(ctx)


# moderngl (5.13) frees nothing of a context it releases (~50 KB of Python objects, and about 200 KB
# more in Mesa): a closed viewer's context serves the next one. As many as a script comparing figures
# keeps open at once, so that each figure's viewers take them again; few, as an idle one holds ~2 MB.
MAX_SPARE_CONTEXTS = 4
_spare_contexts: list[Any] = []


# Contexts of viewers that garbage collection closed, released at the next call that draws: a
# collection may run in the middle of another viewer's GL calls, which releasing there would break.
_unreleased: list[tuple[Any, Renderer]] = []


_releasing = threading.Lock()  # the queue is emptied by whichever thread draws next


def _release_later(ctx: Any, renderer: Renderer) -> None:
    _unreleased.append((ctx, renderer))


def _release_unreleased() -> None:
    with _releasing:
        while _unreleased:
            _release(*_unreleased.pop())


def _context_for_a_viewer() -> Any:
    """A closed viewer's context, else a new one."""
    refuse_forked_gl()  # a context kept by the parent is no more usable than a new one
    _release_unreleased()
    with _releasing:
        if _spare_contexts:
            return _spare_contexts.pop()
    return create_offscreen_context()


def _one_call_at_a_time(method: Callable[..., _Result]) -> Callable[..., _Result]:
    """A Viewer's calls from several threads take turns: its GL context can be current in one thread
    only, and a press half done would be drawn."""
    @functools.wraps(method)
    def in_turn(self: Viewer, *args: Any, **kwargs: Any) -> _Result:
        with self._turn:
            return method(self, *args, **kwargs)
    return in_turn


_open_viewers: weakref.WeakSet[Viewer] = weakref.WeakSet()


@atexit.register
def _close_all() -> None:
    """At exit, whichever of this and weakref.finalize's own hook runs first (it is registered when the
    process makes its first finalizer, numba's say): the viewers still open, those it queued, and the
    contexts kept for the next viewers."""
    for viewer in list(_open_viewers):
        viewer.close()
    _release_unreleased()
    while _spare_contexts:
        _spare_contexts.pop().release()


class Viewer:
    """A scene and its renderer, offscreen. `scene` names a TOML scene file; `empty` starts with the
    camera alone. Bad files raise LoadError, bad keys KeyMapError, bad arguments ValueError, and
    arguments of the wrong kind (keys not a str, a file name not a str or Path) TypeError."""

    def __init__(self, size: Sequence[int] = (800, 600), scene: str | Path | None = None, empty: bool = False,
                 texture: str | Path | None = None) -> None:
        self._size = _checked_size(size)
        _checked_flag(empty, "empty")
        if empty and scene is not None:  # as the command line's --scene and --empty
            raise ValueError("a scene file or empty=True: the two are starting scenes, give one")
        options = StartOptions(scene_file=None if scene is None else _checked_path(scene, "scene"), empty=empty,
                               texture=None if texture is None else _checked_path(texture, "texture"))
        self._turn = threading.RLock()
        self._frontend = OffscreenFrontend(quiet=True)
        # The size, not the Viewer: a closure over it would hold it in a cycle, past its last reference.
        self._viewer = KeyViewer(starting_scene(options), self._frontend, strict=True,
                                 frame_size=_fixed(self._size))
        self._ctx = _context_for_a_viewer()
        with self._ctx:
            self._renderer = Renderer(self._ctx)
        # Garbage collection closes the context too: a notebook rarely says `close`.
        self._closer = weakref.finalize(self, _release_later, self._ctx, self._renderer)
        _open_viewers.add(self)
        self._viewer.start(options, self._renderer.max_texture_side)
        # Whether the next call may skip the scene's check, a pass over every element: only add_mesh
        # sets it, where the scene was checked and its one new element checked where it entered.
        self._checked = False
        self._handed_out = False  # `scene` was read: a hand may change anything in it, in place too

    @property
    def size(self) -> Size:
        """The size `render` draws at when given none; checked when set."""
        return self._size

    @size.setter
    def size(self, size: Sequence[int]) -> None:
        self._size = _checked_size(size)
        self._viewer.frame_size = _fixed(self._size)

    # --- the scene -----------------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        """The scene itself (objects, cameras, lights, modes), for reading or changing by hand. An
        object's `material` set by hand is given to all its parts (a file's materials); its
        `part_materials`, one per material of the file, set after it tell the parts apart."""
        self._handed_out = True
        return self._viewer.scene

    @property
    @_one_call_at_a_time
    def status(self) -> str:
        """What the top of the window says: the target, the moving mode, every switch, the lights and
        the selection ('target objects | rotate local | flat | ...'), which a mode key changes and the
        message does not. A mode set by hand is checked first, as every call checks it."""
        self._check_scene()  # the camera or light it names may be gone
        return status_line(self._viewer.scene)

    @property
    @_one_call_at_a_time
    def message(self) -> str:
        """What the bottom of the window says after the last press or load: the message, and the file
        prompt while `f` holds it open (the keys pressed are typed into it, not done)."""
        if self._viewer.prompt is None:
            return self._viewer.scene.message
        return "\n".join([*self._viewer.scene.message.splitlines(), prompt_line(self._viewer.prompt)])

    @_one_call_at_a_time
    def load(self, path: str | Path) -> Viewer:
        """Any model file the program reads, added as `f` adds it; LoadError on bad input."""
        self._check_open()
        self._viewer.load_model(_checked_path(path, "path"))
        return self

    @_one_call_at_a_time
    def press(self, keys: str) -> Viewer:
        """Keys in the language of --keys: "0 1 F x*5 f=model.obj". ESC (but in the file prompt) ends
        the sequence, as it ends the screenshot command's keys. All or nothing: a key refused (a file
        that does not load, a `u` that would undo to a matrix that cannot be drawn) raises with the
        viewer as it was before the call."""
        if not isinstance(keys, str):
            raise TypeError(f"keys are a str, as --keys takes them (\"0 1 F x*5\"), not {type(keys).__name__}")
        self._check_open()
        # All of them checked before any is pressed; a prompt an earlier call left open is typed into.
        presses = self._viewer.key_presses(keys)
        # The viewer's own fields too (the prompt, what the message says of a model out of view), as they were.
        restore, viewer_fields = self._viewer.scene.restorer(len(presses)), dict(vars(self._viewer))
        try:
            for _ in self._frontend.replay(self._viewer, presses):  # up to ESC, as the screenshot command's keys
                pass
        except BaseException:  # all or nothing, as a bad key's name (an interrupt too): run again, it presses them once
            restore()
            vars(self._viewer).update(viewer_fields)
            raise
        finally:
            self._frontend.quitting = False  # the next sequence is pressed: a notebook has no window to close
        return self

    @_one_call_at_a_time
    def add_mesh(self, positions: Any, faces: Any = None, uvs: Any = None, normals: Any = None,
                 name: str | None = None, colours: Any = None, attributes_per_vertex: bool | None = None,
                 texture: Any = None) -> Viewer:
        """A model from arrays, or from a trimesh.Trimesh or trimesh.Scene given alone (with its uvs,
        texture and vertex colours): positions (V, 3), faces (F, k) of 0-based indices (or a list of
        polygons), uvs and normals per vertex or per corner (`attributes_per_vertex` says which where
        both fit), colours per vertex. `texture`, its own picture in place of the scene's: an (H, W)
        or (H, W, 3 or 4) array of bytes or of 0..1 floats, top row first, a PIL image, or a picture
        file. Without a name, one read from a file takes the file's, as a loaded model does, and
        others are "mesh"."""
        self._check_open()
        _checked_flag(attributes_per_vertex, "attributes_per_vertex", none=True)
        _checked_name(name)
        _refuse_masked(positions=positions, faces=faces, uvs=uvs, normals=normals, colours=colours, texture=texture)
        picture = None if texture is None else _picture_given(texture)
        from_trimesh = faces is None and (hasattr(positions, "geometry")
                                          or (hasattr(positions, "vertices") and hasattr(positions, "faces")))
        if name is None:
            name = (_file_stem(positions) if from_trimesh else None) or "mesh"
        shown_name = kept_name(name)
        if from_trimesh:
            if not (uvs is None and normals is None and colours is None and attributes_per_vertex is None):
                raise ValueError("a trimesh.Trimesh brings its own uvs and colours: give it alone, or give its "
                                 "arrays (mesh.vertices, mesh.faces, normals=mesh.vertex_normals, ...)")
            mesh = mesh_of_trimesh(shown_name, positions)
        elif faces is None:
            raise ValueError("add_mesh needs faces, or a trimesh.Trimesh or trimesh.Scene alone")
        else:
            mesh = build_mesh(name=shown_name, positions=_finite_positions(positions), faces=faces, uvs=uvs,
                              normals=normals, vertex_colours=colours, attributes_per_vertex=attributes_per_vertex,
                              warnings=_transposed_hint(faces))
        refusal = cannot_light(*mesh.bounds)
        if refusal is not None:
            raise ValueError(refusal)
        material = material_for_loaded(mesh, own_picture=picture is not None)
        obj = SceneObject.placed(mesh.name, mesh, material, (0.0, 0.0, 0.0))
        obj.picture = picture
        give_part_materials(obj, from_scene=False)
        self._viewer.add_made(obj)
        self._checked = True
        return self

    # --- pictures ------------------------------------------------------------------------------
    @_one_call_at_a_time
    def render(self, overlay: bool = False, size: Sequence[int] | None = None) -> Image.Image:
        """The picture the window would show (with `overlay`, its text and panels too)."""
        self._check_open()
        _checked_flag(overlay, "overlay")
        shape = self.size if size is None else _checked_size(size)
        _release_unreleased()
        with self._ctx:  # another Viewer's context may be the current one: each draws in its own
            pixels = render_pixels(self._ctx, self._renderer, self._viewer, shape, overlay)
        return_freed_memory()  # as the window does when still: a notebook keeps the process between pictures
        return picture_of(pixels)

    def __repr__(self) -> str:
        """What the viewer holds, in words, drawing nothing: a notebook shows it once closed."""
        scene, (width, height) = self._viewer.scene, self.size
        counts = ", ".join(counted(len(items), what) if isinstance(items, list) else f"{what}s: {type(items).__name__}"
                           for items, what in ((scene.objects, "object"), (scene.cameras, "camera"),
                                               (scene.lights, "light")))  # set by hand, refused at the next call
        return f"<marraztu.Viewer {width}x{height}, {counts}, {'open' if self._closer.alive else 'closed'}>"

    def _repr_png_(self) -> bytes | None:
        if not self._closer.alive:  # None: the notebook shows the text repr instead of a traceback
            return None
        stream = BytesIO()
        self.render().save(stream, format="PNG")
        return stream.getvalue()

    @_one_call_at_a_time
    def probe(self) -> ProbeReport | None:
        """The selected face's probe as numbers; None when there is no face to probe."""
        self._check_open()
        found = probe_scene(self._viewer.scene)
        if found is None:
            return None
        vertices = tuple(_probed_vertex(found, vertex) for vertex in found.vertices)
        return ProbeReport(object=found.obj.name, face=found.face, face_count=found.face_count,
                           material=found.obj.material_name_of_face(found.face), shading=found.shading.value,
                           view=found.view_name,
                           back_face=found.back_face, culled=found.back_face and found.culling,
                           textured=found.textured, vertices=vertices)

    # --- the context ---------------------------------------------------------------------------
    @_one_call_at_a_time
    def close(self) -> None:
        """Releases the renderer's GL objects and hands the context on (kept for the next viewer, or
        released); afterwards the scene, status, message and size can be read, and every other call
        raises ViewerError."""
        self._closer()
        _release_unreleased()
        return_freed_memory()  # a released context's memory stays with glibc otherwise, as a frame's would

    def _check_open(self) -> None:
        if not self._closer.alive:
            raise ViewerError("this Viewer is closed")
        refuse_forked_gl()
        self._check_scene()
        self._checked = False  # until add_mesh says otherwise: other calls' changes are not looked into

    def _check_scene(self) -> None:
        """The scene's check (Scene.check_by_hand), where it may have changed since the last: it is out,
        or a call other than add_mesh came between (whose own element was checked where it entered)."""
        if self._handed_out or not self._checked:
            self._viewer.scene.check_by_hand()

    def __reduce__(self) -> NoReturn:
        """copy.copy would share the GL context (closing the copy closed the original); deepcopy and pickle
        failed on its lock, deep in the copy module. `__reduce__` is what all three ask first."""
        raise TypeError("a Viewer holds a GL context: it is not copied or pickled; copy.deepcopy(v.scene) "
                        "copies its scene, and a new Viewer draws another")

    def __enter__(self) -> Viewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _probed_vertex(found: Any, vertex: Any) -> ProbedVertex:
    shares = tuple(LightShare(light=term.name, reaches=term.reaches, n_dot_l=float(term.n_dot_l),
                              highlight=float(term.highlight), diffuse=_triple(term.diffuse),
                              specular=_triple(term.specular), to_light=_triple(term.to_light),
                              halfway=_triple(term.halfway)) for term in vertex.terms.lights)
    shown = found.displayed(vertex)
    colour = tuple(int(c) for c in (shown if shown is not None else vertex.lit_bytes))
    tints = found.obj.mesh.vertex_colours
    tint = None if tints is None else tuple(int(c) for c in tints[vertex.vertex])
    return ProbedVertex(vertex=vertex.vertex, world_position=_triple(vertex.world_position),
                        normal=_triple(vertex.world_normal), n_dot_v=vertex.n_dot_v,
                        ambient=_triple(vertex.terms.ambient), lights=shares, total=_triple(vertex.shown),
                        colour=colour, vertex_colour=tint)  # type: ignore[arg-type]


def _file_stem(model: Any) -> str | None:
    """The stem of the file trimesh read `model` from (its .source, since trimesh 4.6.0); None where it
    was made in Python."""
    file_name = getattr(getattr(model, "source", None), "file_name", None)
    return Path(file_name).stem or None if isinstance(file_name, str) else None


def _refuse_masked(**arrays: Any) -> None:
    """numpy reads a masked array's hidden values as any others: they would be drawn, so a mask that
    hides any is refused (one that hides none is its values)."""
    for what, values in arrays.items():
        if np.ma.is_masked(values):
            raise ValueError(f"{what} has masked values, which would be drawn as any others: give "
                             f"np.ma.filled({what}, value) or leave their rows out")


def _transposed_hint(faces: Any) -> tuple[str, ...]:
    """A note where faces look given transposed: (3, F) of triangles reads as three polygons of F
    corners, which draw, so no error says so; a ValueError saying so where (3 or 4, F) faces of F
    below 3, refused as faces of too few corners, may be (F, 3 or 4) ones turned."""
    # Numbers only: it runs before build_mesh checks the faces, whose error then says what is wrong.
    numbers = isinstance(faces, np.ndarray) and faces.ndim == 2 and faces.dtype.kind in "biuf"
    rows, columns = np.shape(faces) if numbers else (0, 0)
    # A polygon that lists a vertex twice: a column of a mesh's triangles, not a real polygon's corners.
    if rows in (3, 4) and columns > 4 and any(np.unique(row).size < columns for row in faces):
        return (f"{rows} polygons of {columns} corners: for {columns} polygons of {rows}, give faces.T",)
    if rows in (3, 4) and 0 < columns < 3:  # refused as faces of too few corners: say why they may be
        raise ValueError(f"faces of shape {np.shape(faces)} are {rows} faces of {counted(columns, 'corner')}, and "
                         f"a face needs at least 3: for {counted(columns, 'face')} of {rows}, give faces.T")
    return ()


def _picture_given(texture: Any) -> np.ndarray:
    """add_mesh's texture as the renderer takes it: a file read as a model's picture is, or a picture
    handed over in code, as a trimesh material's is."""
    if isinstance(texture, (str, os.PathLike)):
        return load_image(texture)
    return picture_rgb(texture)


def _finite_positions(positions: Any) -> np.ndarray:
    """Checked here, where the data enters: the GPU holds float32, and NaN has no place on screen."""
    table = real_numbers(positions, "positions must be real numbers, (V, 3)")
    if table.ndim != 2 or table.shape[1] != 3 or table.shape[0] == 0:
        transposed = table.ndim == 2 and table.shape[0] == 3 and table.shape[1] > 0
        raise ValueError(f"positions must have shape (V, 3), not {table.shape}"
                         + (f": for {table.shape[1]} positions, give positions.T" if transposed else ""))
    if table.shape[0] >= INDEX_LIMIT:  # before any pass over them: a broadcast view may be endless
        raise ValueError(f"a mesh holds fewer than {INDEX_LIMIT} positions")
    if not holds_in_float32(table):
        raise ValueError("positions must be finite numbers a float32 can hold")
    # The scene's own: a later change to the caller's array must not move it. A plain list or tuple was
    # read into a new table; an array is copied where the table shares its memory; anything else numpy
    # read (a DataFrame...) is copied, rather than asked for its numbers a second time.
    if type(positions) in (list, tuple):
        return table
    if isinstance(positions, (np.ndarray, memoryview)) and not np.may_share_memory(table, positions):
        return table
    return table.copy()


__all__ = ["KeyMapError", "LightShare", "LoadError", "ProbeReport", "ProbedVertex", "Viewer", "ViewerError"]
