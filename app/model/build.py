"""A Mesh from plain tables: every normal and texture coordinate a file lacks, derived.

Every reader (OBJ and the formats beyond it) and the programming interface end here, so a model
gets the same normals and coordinates whichever way it came in.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from numbers import Real
from types import ModuleType

import numpy as np

from marraztu.model.geometry import FLOAT32_MAX, column_bounds, holds_in_float32, unit_rows
from marraztu.model.mesh import INDEX, INDEX_LIMIT, Mesh, corners_of_polygons, counted, fan_gather, polygons_of_corners
from marraztu.model.threads import arrays_equal, converted, each, gathered, one_per_thread, pieces, weighed_pieces

# Zero-area faces get a fallback normal; "zero" is relative to the model's size.
DEGENERATE_AREA = 1e-12
FALLBACK_NORMAL = np.array([0.0, 0.0, 1.0])
# Per-corner values as the readers give them: a table and, per corner, its row (-1: none, derive it).
CornerSource = tuple[np.ndarray, np.ndarray]


def build_mesh(
    name: str,
    positions: np.ndarray | Sequence[Sequence[float]],
    faces: Sequence[Sequence[int]] | np.ndarray,
    uvs: np.ndarray | Sequence[Sequence[float]] | None = None,
    normals: np.ndarray | Sequence[Sequence[float]] | None = None,
    base_colour: tuple[float, float, float] | None = None,
    file_material: dict[str, object] | None = None,
    warnings: Sequence[str] = (),
    vertex_colours: np.ndarray | Sequence[Sequence[float]] | None = None,
    attributes_per_vertex: bool | None = None,
    face_sizes: np.ndarray | Sequence[int] | None = None,
) -> Mesh:
    """A Mesh from plain tables, with normals and texture coordinates derived as the loader does.

    ``faces`` holds 0-based vertex indices, one sequence per polygon (3 or more); with ``face_sizes``,
    one flat array of every polygon's corners, one polygon after another, of those sizes. ``uvs`` and
    ``normals`` have one row per position, or one per corner in the order the faces list their
    corners; their row count says which, and ``attributes_per_vertex`` where both counts are equal.
    A row with a NaN or an infinity means "derive this one". ``vertex_colours`` are per position: RGB
    or RGBA, bytes (0..255) or floats (0..1). Raises ValueError for impossible input (this is a
    programming interface).
    """
    points = real_numbers(positions, "positions must be real numbers, (V, 3)").reshape(-1, 3)
    corner_vertex, face_start = (_listed_polygons(faces, len(points)) if face_sizes is None
                                 else _sized_polygons(faces, face_sizes, len(points)))
    given_uv, given_normals = (
        None if values is None else _given_table(what, values, width, corner_vertex, len(points), attributes_per_vertex)
        for what, values, width in (("uvs", uvs, 2), ("normals", normals, 3)))
    mesh = derive_mesh(name, points, corner_vertex, face_start, given_uv, given_normals,
                       base_colour, file_material, tuple(warnings))
    if vertex_colours is None:
        return mesh
    return replace(mesh, vertex_colours=colour_bytes(vertex_colours, len(points)))


# The renderer tints by vertex colours only: a file's colours per face (a PLY's, an OFF's) are read past.
FACE_COLOURS_NOTE = "colours given per face are not drawn, only those per vertex"


def colour_fractions(colours: np.ndarray) -> np.ndarray:
    """Colours a file gives as 0..1 or as 0..255, as fractions 0..1, the largest value saying which: one
    above 2, or whole numbers of which the largest is above 1, say 0..255 (127.5 too), divided by 255;
    a largest value in 1..2 with a fraction is a float colour a little past 1 (1.0001 made sRGB), not
    0..255's 1, and kept."""
    largest = colours.max(initial=0.0)
    with np.errstate(invalid="ignore"):
        bytes_like = largest > 2.0 or (largest > 1.0 and bool((colours == np.round(colours)).all()))
    return colours / 255.0 if bytes_like else colours


def colour_bytes(colours: np.ndarray | Sequence[Sequence[float]], rows: int) -> np.ndarray:
    """(rows, 3) uint8 from RGB or RGBA rows of bytes (0..255) or of floats (0..1); alpha is dropped."""
    table = _number_table(colours, f"vertex colours must be {rows} rows of RGB or RGBA", "vertex colours")
    if table.ndim != 2 or table.shape[0] != rows or table.shape[1] not in (3, 4):
        raise ValueError(f"vertex colours must be {rows} rows of RGB or RGBA, not shape {table.shape}")
    return _rgb_bytes(table, "vertex colours")


def picture_bytes(picture: np.ndarray | Sequence[Sequence[float]]) -> np.ndarray:
    """(H, W, 3) uint8, top row first, from an (H, W) grey or (H, W, 3 or 4) picture of bytes (0..255)
    or of floats (0..1), as colours are given; alpha is dropped. Its size is the caller's to check."""
    table = _number_table(picture, "a texture must be an array of pixels", "texture pixels")
    if table.ndim not in (2, 3) or (table.ndim == 3 and table.shape[2] not in (3, 4)) or 0 in table.shape:
        raise ValueError(f"a texture must be an (H, W) grey or (H, W, 3 or 4) picture, not shape {table.shape}")
    grey = table.ndim == 2
    rgb = _rgb_bytes(table[..., None] if grey else table, "texture pixels")
    return np.ascontiguousarray(rgb.repeat(3, axis=2) if grey else rgb)


def _number_table(values: object, ragged: str, what: str) -> np.ndarray:
    try:
        table = np.asarray(values)
        if table.dtype.kind == "O":  # objects (pandas gives these): numbers as numpy reads them, ints as ints
            table = np.array(table.tolist())
    except (ValueError, TypeError):  # ragged rows
        raise ValueError(ragged) from None
    if table.dtype.kind not in "biuf":  # text or objects: not read as numbers
        raise ValueError(f"{what} must be numbers")
    return table


def _rgb_bytes(table: np.ndarray, what: str) -> np.ndarray:
    """The first three channels of the last axis as bytes: integers kept, floats in 0..1 scaled."""
    rgb = table[..., :3]
    if np.issubdtype(rgb.dtype, np.integer):
        if rgb.size and (rgb.min() < 0 or rgb.max() > 255):
            raise ValueError(f"integer {what} must lie in 0..255")
        return rgb.astype(np.uint8)
    floats = rgb.astype(np.float64)
    if not np.isfinite(floats).all() or (floats.size and (floats.min() < 0.0 or floats.max() > 1.0)):
        in_bytes_range = np.isfinite(floats).all() and floats.min() >= 0.0 and floats.max() <= 255.0
        advice = "; for 0..255, give bytes (.astype(np.uint8)) or divide by 255" if in_bytes_range else ""
        raise ValueError(f"float {what} must be finite and lie in 0..1{advice}")
    return np.rint(floats * 255.0).astype(np.uint8)


def _given_table(what: str, values: np.ndarray | Sequence[Sequence[float]], width: int, corner_vertex: np.ndarray,
                 vertex_count: int, per_vertex: bool | None) -> CornerSource:
    """Per-vertex or per-corner values as a (table, per-corner row) pair; a corner whose row is not
    finite gets -1 (derived instead, as where a file's uv is not). `what` names them in errors."""
    table = real_numbers(values, f"{what} must be rows of {width} real numbers")
    corners = corner_vertex.size
    if table.ndim != 2 or table.shape[1] != width or table.shape[0] not in (vertex_count, corners):
        raise ValueError(f"{what} need one row per vertex, shape ({vertex_count}, {width}), or one per corner in "
                         f"the order the faces list them, shape ({corners}, {width}); not {table.shape}")
    if per_vertex is None:
        per_vertex = table.shape[0] == vertex_count
        # A table that fits both is ambiguous unless the faces list every vertex once, in order.
        if vertex_count == corners and not np.array_equal(corner_vertex, np.arange(corners)):
            raise ValueError(f"{what} have {corners} rows, as many as the vertices and as the corners: say which "
                             "with attributes_per_vertex=True or False")
    if table.shape[0] != (vertex_count if per_vertex else corners):
        raise ValueError(f"{what} given per {'vertex' if per_vertex else 'corner'} need shape "
                         f"({vertex_count if per_vertex else corners}, {width}), not {table.shape}")
    finite = np.isfinite(table).all(axis=1)
    if not holds_in_float32(np.where(finite[:, None], table, 0.0)):  # the GPU holds 32-bit floats, as a file's vt
        raise ValueError(f"{what} must lie within 32-bit floats (3.4e38)")
    rows = corner_vertex if per_vertex else np.arange(corners)
    return table, np.where(~finite[rows], -1, rows)


def real_numbers(values: object, refusal: str) -> np.ndarray:
    """float64 from numbers; ValueError(refusal) for anything else: numpy would drop the imaginary part
    of a complex number, read the text "1.5" as a number, and give ragged rows as objects."""
    try:
        table = np.asarray(values)
    except (TypeError, ValueError):
        raise ValueError(refusal) from None
    numbers_only = table.dtype.kind in "biuf" or (
        table.dtype.kind == "O" and all(isinstance(value, Real) for value in table.flat))  # pandas gives these
    if not numbers_only:  # text, complex numbers, times, or objects that are not all real numbers
        raise ValueError(refusal)
    try:
        return table.astype(np.float64, copy=False)  # float64 already: the caller's array, not a copy
    except OverflowError:  # a Python int past a double's range
        raise ValueError(refusal) from None


_FACES_SHAPE = "faces must be rows of vertex indices, (F, k), or a list of polygons"


def _mesh_limit() -> str:
    """What a mesh holds at most, for the refusal of a count past it."""
    return f"a mesh holds fewer than {INDEX_LIMIT} positions and corners"


def _listed_polygons(faces: Sequence[Sequence[int]] | np.ndarray, vertex_count: int) -> tuple[np.ndarray, np.ndarray]:
    """Polygons given as a list of corner lists or as an (F, k) array, as corners (their vertex rows)
    and each polygon's first corner."""
    if isinstance(faces, np.ndarray) and faces.dtype.kind != "O" and faces.ndim != 2:  # a flat index buffer, say
        raise ValueError(f"{_FACES_SHAPE}, not an array of shape {faces.shape}")
    if isinstance(faces, (str, bytes)):  # each letter would be a polygon of one corner
        raise ValueError(f"{_FACES_SHAPE}, not text")
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        if faces.size >= INDEX_LIMIT:  # before any copy: a broadcast view costs nothing to make
            raise ValueError(_mesh_limit())
        sizes, given = np.full(faces.shape[0], faces.shape[1], dtype=np.int64), faces.ravel()
    else:
        try:
            lists = [list(face) for face in faces]
        except TypeError:  # a number, or a list of numbers, where polygons were wanted
            raise ValueError(_FACES_SHAPE) from None
        sizes = np.array([len(face) for face in lists], dtype=np.int64)
        given = np.array([index for face in lists for index in face])
    _check_face_sizes(sizes)
    face_start = np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)
    return _vertex_rows(given, face_start, vertex_count), face_start


def _vertex_rows(given: np.ndarray, face_start: np.ndarray, vertex_count: int) -> np.ndarray:
    """The corners as int64 rows of the vertex table; ValueError naming the face of one that is none."""
    def refusal(value: int, corner: int) -> str:
        face = int(np.searchsorted(face_start, corner, side="right")) - 1
        return f"face {face} refers to vertex {value}, but there are {vertex_count} (0-based)"

    return checked_vertex_rows(given, vertex_count, refusal)


def checked_vertex_rows(given: np.ndarray, vertex_count: int, refusal: Callable[[int, int], str],
                        not_whole: str = "face indices must be whole numbers (0-based vertex rows)") -> np.ndarray:
    """Corners (any shape) as int64 rows of a table of `vertex_count` vertices; ValueError of
    refusal(value, flat place) for the first that names none, past int64 too, as given."""
    corners = whole_numbers(given, not_whole, past_int64=refusal)
    if corners.size and (corners.min() < 0 or corners.max() >= vertex_count):  # no mask as long as the mesh
        corner = int(np.argmax((corners < 0) | (corners >= vertex_count)))
        raise ValueError(refusal(int(corners.flat[corner]), corner))
    return corners


def _check_face_sizes(sizes: np.ndarray) -> None:
    """ValueError for no face at all, or for the first face of fewer than 3 vertices (0-based)."""
    if sizes.size == 0:
        raise ValueError("a mesh needs at least one face")
    if sizes.min() < 3:
        face = int(np.argmax(sizes < 3))
        raise ValueError(f"face {face} has {counted(int(sizes[face]), 'vertex', 'vertices')}: a face needs at least 3")


def _sized_polygons(corners: np.ndarray | Sequence[int], sizes: np.ndarray | Sequence[int], vertex_count: int
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Polygons given as their corners one after another (flattened) and each one's size, as corners
    (their vertex rows) and each polygon's first corner."""
    given = whole_numbers(np.asarray(sizes).ravel(), "face sizes must be whole numbers")
    _check_face_sizes(given)
    if given.size >= INDEX_LIMIT or given.max() >= INDEX_LIMIT:  # before a sum that could wrap
        raise ValueError(_mesh_limit())
    face_start = np.concatenate(([0], np.cumsum(given)))
    try:
        flat = np.asarray(corners)
    except ValueError:  # polygons of several sizes listed as such
        raise ValueError("with face_sizes, faces are every polygon's corners in one flat array") from None
    if flat.size != face_start[-1]:
        raise ValueError(f"faces of these sizes hold {face_start[-1]} corners, not {flat.size}")
    return _vertex_rows(flat.ravel(), face_start, vertex_count), face_start


def _past_any_mesh(value: int, at: int) -> str:
    return f"{value} is no vertex index or face size: {_mesh_limit()}"


def whole_numbers(indices: np.ndarray, refusal: str = "face indices must be whole numbers (0-based vertex rows)",
                  past_int64: Callable[[int, int], str] = _past_any_mesh) -> np.ndarray:
    """Vertex indices (or face sizes) as int64; 1.5 or "a" is refused, not rounded or read as something
    else, and a number past int64 (2**63 or more) is refused naming it, not wrapped to a negative one:
    `past_int64` says so, given the number and its place."""
    given = indices
    if indices.dtype.kind == "i":
        return indices.astype(np.int64, copy=False)
    if indices.dtype.kind == "O":  # a (F, k) array of objects, as pandas gives: whole numbers in them too
        indices = real_numbers(indices, refusal)
    if indices.dtype.kind == "u":
        past = indices > np.iinfo(np.int64).max
    elif indices.dtype.kind == "f" and np.isfinite(indices).all() and (indices == np.round(indices)).all():
        past = np.abs(indices) >= 2.0**63
    else:
        raise ValueError(refusal)
    if past.any():
        at = int(np.argmax(past))
        raise ValueError(past_int64(int(given.flat[at]), at))
    return indices.astype(np.int64, copy=False)


def derive_mesh(name: str, positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray,
                 uv: CornerSource | None, normals: CornerSource | None,
                 base_colour: tuple[float, float, float] | None, file_material: dict[str, object] | None,
                 notes: tuple[str, ...]) -> Mesh:
    """The Mesh, with every normal and texture coordinate the file lacks derived. Never NaN.

    The tables are checked already (every loader and the API check them): face_start runs from 0, each
    face has 3 corners or more, and every index is in range.
    """
    if max(positions.shape[0], corner_vertex.size) >= INDEX_LIMIT:
        raise ValueError(_mesh_limit())
    sizes = np.diff(face_start)
    bounds = column_bounds(positions)
    face_normals, degenerate = _face_normals(positions, corner_vertex, face_start, sizes, bounds)
    if degenerate.any():
        notes += (_zero_area_note(int(degenerate.sum())),)
    shape = _Shape(positions, corner_vertex, face_start, sizes, bounds, face_normals, degenerate)
    uvs, vertex_normals, per_position, averaged = _uvs_and_normals(shape, uv, normals)
    return Mesh(
        name=name,
        positions=np.ascontiguousarray(positions, dtype=np.float64),
        corner_vertex=np.ascontiguousarray(corner_vertex, dtype=INDEX),
        uvs=uvs,
        normals=vertex_normals,
        face_start=np.ascontiguousarray(face_start, dtype=INDEX),
        face_normals=converted(face_normals, np.float32),
        base_colour=base_colour,
        file_material=file_material,
        warnings=notes,
        attributes_per_position=per_position,
        normals_averaged=averaged,
    )


_FALLBACK_NORMAL_WORDS = " (given a fallback normal)"  # ends the zero-area note, which only derive_mesh writes


def _zero_area_note(faces: int) -> str:
    return counted(faces, "zero-area face") + _FALLBACK_NORMAL_WORDS


def _is_zero_area_note(note: str) -> bool:
    return note.endswith(_FALLBACK_NORMAL_WORDS)


def scaled_mesh(mesh: Mesh, factors: tuple[float, float, float]) -> Mesh:
    """The mesh as read at `factors` times its size along x, y and z (each > 0), as the file written so
    would be read: its positions stretched, its face normals and the file's own normals turned as the
    inverse transpose turns them, normals it averaged averaged again from the turned faces (and the
    zero-area faces' note told again), and its texture coordinates kept (they are the surface's).
    Itself where every factor is 1."""
    if factors == (1.0, 1.0, 1.0):
        return mesh
    stretch = np.asarray(factors, np.float64)
    whole_origin = None if mesh.whole_gpu_origin is None else mesh.whole_gpu_origin * stretch
    stretched = replace(mesh, positions=mesh.positions * stretch, whole_gpu_origin=whole_origin)
    if np.all(stretch == stretch[0]):  # a uniform scale leaves every direction as it was
        return stretched
    turn = stretch.min() / stretch  # the inverse's direction, its entries at most 1: none overflows
    averaged = mesh.normals_averaged
    if averaged is False:  # every normal the file's own
        return replace(stretched, normals=unit_rows(mesh.normals * turn, np.float32)[0],
                       face_normals=unit_rows(mesh.face_normals * turn, np.float32)[0])
    # The average of turned faces is not the turned average: derived again, the file's own normals turned.
    rows = mesh.corner_vertex if mesh.attributes_per_position else np.arange(mesh.corner_vertex.size, dtype=INDEX)
    given = None if averaged is True else (unit_rows(mesh.normals * turn, np.float32)[0],
                                           np.where(averaged[rows], -1, rows))
    again = derive_mesh(mesh.name, stretched.positions, mesh.corner_vertex, mesh.face_start, (mesh.uvs, rows),
                        given, None, None, ())
    return replace(stretched, uvs=again.uvs, normals=again.normals, face_normals=again.face_normals,
                   attributes_per_position=again.attributes_per_position, normals_averaged=again.normals_averaged,
                   warnings=_with_zero_area_note(mesh.warnings, again.warnings))


def _with_zero_area_note(notes: tuple[str, ...], derived: tuple[str, ...]) -> tuple[str, ...]:
    """`notes` with their zero-area note (derive_mesh's, known by its words) replaced by the `derived`
    mesh's own notes, in its place, or after them where they had none."""
    old = next((at for at, note in enumerate(notes) if _is_zero_area_note(note)), len(notes))
    return notes[:old] + derived + notes[old + 1:]


@dataclass(frozen=True)
class _Shape:
    """What the normals and texture coordinates are derived from."""

    positions: np.ndarray
    corner_vertex: np.ndarray
    face_start: np.ndarray
    sizes: np.ndarray
    bounds: tuple[np.ndarray, np.ndarray]
    face_normals: np.ndarray  # (F, 3), zero for the degenerate faces until _fill_degenerate
    degenerate: np.ndarray


def _uvs_and_normals(shape: _Shape, uv: CornerSource | None, normals: CornerSource | None
                     ) -> tuple[np.ndarray, np.ndarray, bool, bool | np.ndarray]:
    """The uvs and unit normals, whether their rows are per position rather than per corner, and which
    normals were averaged (Mesh.normals_averaged)."""
    by_position = _per_position_sources(shape.corner_vertex, shape.positions.shape[0], uv, normals)
    # Per position where each position has one uv and one normal: derived once each, not once per corner.
    attributes = None if by_position is None else _attributes(shape, *by_position, per_position=True)
    if attributes is not None:
        return attributes[0], attributes[1], True, attributes[2]
    uvs, vertex_normals, averaged = _attributes(shape, uv, normals, per_position=False)  # never None per corner
    return uvs, vertex_normals, False, averaged


def _per_position_sources(corner_vertex: np.ndarray, vertex_count: int, uv: CornerSource | None,
                          normals: CornerSource | None) -> tuple[CornerSource | None, CornerSource | None] | None:
    """The file's vt and vn rows per position, where every corner of a position names the same ones
    (as `f 1/1/1 2/2/2 3/3/3` does); None where some position's corners differ."""
    representative = None  # a corner of each position (0 for unused ones), made when first needed
    sources: list[CornerSource | None] = []
    for source in (uv, normals):
        if source is None:
            sources.append(None)
            continue
        table, index = source
        if table.shape[0] >= vertex_count and arrays_equal(index, corner_vertex):  # each the position's own row
            sources.append((table, np.arange(vertex_count)))
            continue
        if representative is None:
            representative = np.zeros(vertex_count, np.int64)
            representative[corner_vertex] = np.arange(corner_vertex.size)
        position_index = index[representative]
        if not np.array_equal(position_index[corner_vertex], index):
            return None
        sources.append((table, position_index))
    return sources[0], sources[1]


def _attributes(shape: _Shape, uv: CornerSource | None, normals: CornerSource | None, per_position: bool
                ) -> tuple[np.ndarray, np.ndarray, bool | np.ndarray] | None:
    """The uvs and unit normals, a row per position (`uv` and `normals` give their rows per position)
    or per corner, and which normals were averaged. None per position where some used position
    touches no face with an area: its corners take their own faces' normals, which may differ."""
    row_vertex = None if per_position else shape.corner_vertex  # None: the rows are the positions
    rows = shape.positions.shape[0] if per_position else shape.corner_vertex.size
    vertex_normals, missing = _usable_normals(normals, rows)
    # A flag where all or none are (no table as long as the rows), the rows themselves where some are.
    some = bool(missing.any())
    averaged = missing.copy() if some and not missing.all() else some
    if some:
        missing = _fill_vertex_normals(vertex_normals, missing, shape, row_vertex)
    if per_position and missing.any():
        used = np.zeros(rows, bool)
        used[shape.corner_vertex] = True
        if (missing & used).any():
            return None  # before _fill_degenerate changes the face normals the per-corner try starts from
        vertex_normals[missing] = FALLBACK_NORMAL  # positions no face uses: never drawn
        missing[:] = False
    if shape.degenerate.any():
        _fill_degenerate(shape, vertex_normals, row_vertex)
    if missing.any():
        corners = np.flatnonzero(missing)  # no usable face touches their position: take their face's
        vertex_normals[corners] = shape.face_normals[polygons_of_corners(shape.face_start, corners)]
    return _uvs(uv, shape.positions, row_vertex, shape.bounds), vertex_normals, averaged


def _positions_of(rows: np.ndarray, row_vertex: np.ndarray | None) -> np.ndarray:
    """The position each of these rows of uvs and normals belongs to (row_vertex None: rows are positions)."""
    return rows if row_vertex is None else row_vertex[rows]


def _uvs(uv: CornerSource | None, positions: np.ndarray, row_vertex: np.ndarray | None,
         bounds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The file's vt per row, and the bounding-box projection where a row has none."""
    if uv is None:
        return _bounding_box_uv(positions, row_vertex, bounds)
    table, index = uv
    uvs = np.empty((index.shape[0], 2), np.float32)

    def piece(rows: slice) -> None:
        block = uvs[rows]
        with np.errstate(over="ignore"):  # past float32's range: infinite, then its largest
            block[:] = np.take(table, index[rows], axis=0)  # np.take gathers small rows faster than fancy indexing
        np.clip(block, -FLOAT32_MAX, FLOAT32_MAX, out=block)

    each(piece, pieces(index.shape[0]))
    without = np.flatnonzero(index < 0)
    if without.size:
        uvs[without] = _bounding_box_uv(positions, _positions_of(without, row_vertex), bounds)
    return uvs


def _face_normals(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray,
                  sizes: np.ndarray, bounds: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Unit polygon normals by Newell's method, and which faces have (almost) no area (left zero).

    Newell's sum of p_i x p_(i+1) is unchanged by moving the origin to the first vertex, where it
    becomes the sum of the fan triangles' cross products: cheaper, and exact far from the origin.
    numpy works on one contiguous array per axis: gathers from and arithmetic on (N,) arrays run at
    memory speed, where the columns of an (N, 3) array are strided. The compiled loop, where it is
    loaded, does the same arithmetic polygon by polygon.
    """
    smallest = DEGENERATE_AREA * _size_squared(bounds)
    compiled = _compiled_loops(positions, corner_vertex, face_start)
    if compiled is not None:
        return _compiled_face_normals(compiled, positions, corner_vertex, face_start, smallest)
    if _one_small_size(sizes):  # triangles, quads...: each polygon's fans summed in place
        sums = _fan_sums(positions, corner_vertex.reshape(-1, int(sizes[0])))  # a view of the corners
    else:  # each fan a polygon of its own, then the fans of each polygon added in fan order
        sums = _block_sums(positions, corner_vertex, face_start, sizes)
    return sums.T, _made_unit(sums, smallest)


def _made_unit(sums: np.ndarray, smallest: float) -> np.ndarray:
    """Each polygon's (3, F) sum made unit length in place; which are (almost) no length (zeroed)."""
    degenerate = np.empty(sums.shape[1], bool)

    def unit(polygons: slice) -> None:  # in place, piece by piece: no temporary as long as the mesh
        piece = sums[:, polygons]
        with np.errstate(all="ignore"):
            x, y, z = piece
            length = np.sqrt(x * x + y * y + z * z)
            flat = degenerate[polygons]
            np.logical_or(~np.isfinite(length), length <= smallest, out=flat)
            piece /= np.where(flat, 1.0, length)
        piece[:, flat] = 0.0

    each(unit, pieces(sums.shape[1], _CROSS_CHUNK))
    return degenerate


_FAN_BLOCK = 1 << 16  # fans gathered at once where polygons are of many sizes, or huge


def _block_sums(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray, sizes: np.ndarray
                ) -> np.ndarray:
    """(3, F): each polygon's fan sum, in fan order, polygons a block of about _FAN_BLOCK fans at a time
    (a polygon of more fans alone, its fans a block at a time), so that no table is as long as the
    mesh's fans."""
    sums = np.empty((3, sizes.size), positions.dtype)
    axes = np.ascontiguousarray(positions.T)  # once, not once a block
    for block in weighed_pieces(sizes - 2, _FAN_BLOCK):
        low, high = block.start, block.stop
        first, stop = int(face_start[low]), int(face_start[high])
        if sizes[low] - 2 > _FAN_BLOCK:  # alone in its block
            sums[:, low] = _huge_polygon_sum(positions, axes, corner_vertex[first:stop])
        else:
            fans = fan_gather(corner_vertex[first:stop], face_start[low:high + 1] - first).reshape(-1, 3)
            sums[:, low:high] = _fans_added(_fan_sums(positions, fans, axes), sizes[low:high])
    return sums


def _huge_polygon_sum(positions: np.ndarray, axes: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """(3,): one polygon's fan sum, in fan order, its fans a block at a time: each block's running sum
    (np.cumsum adds one after another, as the loop does) starts from the blocks' before it."""
    total = None
    for start in range(1, corners.size - 1, _FAN_BLOCK):
        stop = min(start + _FAN_BLOCK, corners.size - 1)
        fans = np.empty((stop - start, 3), corners.dtype)
        fans[:, 0], fans[:, 1], fans[:, 2] = corners[0], corners[start:stop], corners[start + 1:stop + 1]
        block = _fan_sums(positions, fans, axes)
        with np.errstate(all="ignore"):
            if total is not None:
                block[:, 0] += total
            total = np.cumsum(block, axis=1)[:, -1]
    return total


def _fans_added(fan_sums: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """(3, F): each polygon's first fan's sum, then its others added one by one in fan order, as the
    one-size path and the compiled loop add them (np.add.reduceat would add the later ones pairwise)."""
    firsts = np.concatenate(([0], np.cumsum(sizes - 2)[:-1]))
    sums = fan_sums[:, firsts]
    later = np.ones(fan_sums.shape[1], bool)
    later[firsts] = False
    polygon = np.repeat(np.arange(sizes.size), sizes - 2)[later]
    with np.errstate(all="ignore"):  # inf + -inf: a NaN the degenerate test catches
        for axis in range(3):
            np.add.at(sums[axis], polygon, fan_sums[axis, later])
    return sums


def _compiled_loops(floats: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray) -> ModuleType | None:
    """marraztu.model.compiled where this process has imported it already and the float table
    (positions or face normals) and the corners are the types its machine code takes (writable ones:
    numba types read-only arrays apart); else None, and numpy does the work."""
    if "marraztu.model.compiled" not in sys.modules:
        return None
    if not (floats.dtype == np.float64 and all(table.flags.c_contiguous and table.flags.writeable
                                               for table in (floats, corner_vertex, face_start))
            and corner_vertex.dtype == INDEX and face_start.dtype == INDEX):
        return None
    try:
        from marraztu.model import compiled  # imported, or being imported by another thread: this waits
    except ImportError:  # that import failed: numba cannot be loaded here
        return None
    return compiled


def _compiled_face_normals(compiled: ModuleType, positions: np.ndarray, corner_vertex: np.ndarray,
                           face_start: np.ndarray, smallest: float) -> tuple[np.ndarray, np.ndarray]:
    """_face_normals's outcome by the compiled loop, in pieces of faces on threads."""
    faces = face_start.size - 1
    normals, degenerate = np.empty((faces, 3)), np.empty(faces, bool)
    each(lambda rows: compiled.polygon_normals(positions, corner_vertex, face_start, smallest, rows.start, rows.stop,
                                               normals, degenerate), pieces(faces))
    return normals, degenerate


# Polygons of one size up to this many corners are worked on corner column by corner column; beyond
# it, one pass per column would cost corners x positions for a few huge polygons.
MAX_COLUMN_SIZE = 16


def _one_small_size(sizes: np.ndarray) -> bool:
    return bool(sizes.min() == sizes.max() and sizes[0] <= MAX_COLUMN_SIZE)


_CROSS_CHUNK = 1 << 14  # polygons per piece: a dozen temporaries of this many numbers stay in cache


def _fan_sums(positions: np.ndarray, polygons: np.ndarray, axes: np.ndarray | None = None) -> np.ndarray:
    """(3, N): for each of the (N, k) polygons, the sum of (p_i - p_0) x (p_(i+1) - p_0) over its fan,
    in fan order. `axes`: the positions as (3, V) rows, where the caller made them once for many calls.

    In pieces, so that the gathered coordinates and products are cache-sized temporaries instead of a
    dozen arrays as long as the mesh in fresh memory; the pieces are worked on in threads."""
    x, y, z = np.ascontiguousarray(positions.T) if axes is None else axes
    out = np.empty((3, polygons.shape[0]), positions.dtype)

    def piece(rows: slice) -> None:
        # Each corner column as numpy's own index type, once: a gather by int32 indices converts them.
        block = polygons[rows].T.astype(np.intp)
        first = block[0]
        with np.errstate(all="ignore"):
            x0, y0, z0 = x.take(first), y.take(first), z.take(first)
            for corner in range(1, polygons.shape[1] - 1):
                second, third = block[corner], block[corner + 1]
                ax, ay, az = x.take(second) - x0, y.take(second) - y0, z.take(second) - z0
                bx, by, bz = x.take(third) - x0, y.take(third) - y0, z.take(third) - z0
                cross = (ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)
                if corner == 1:  # set, not added to zeros: 0.0 + -0.0 would lose the zero's sign
                    out[:, rows] = cross
                else:
                    out[:, rows] += cross

    each(piece, pieces(polygons.shape[0], _CROSS_CHUNK))
    return out


def _size_squared(bounds: tuple[np.ndarray, np.ndarray]) -> float:
    low, high = bounds
    with np.errstate(all="ignore"):
        size = float(np.sum((high - low) ** 2))
    return size if np.isfinite(size) else 0.0


def _usable_normals(normals: CornerSource | None, rows: int) -> tuple[np.ndarray, np.ndarray]:
    """(rows, 3) float32 unit normals from the file's vn, and which rows lack a usable one.

    Normalised once per vn row, not per corner; a zero-length vn is not usable.
    """
    if normals is None:
        return np.zeros((rows, 3), dtype=np.float32), np.ones(rows, dtype=bool)
    table, index = normals
    unit, ok = unit_rows(table, np.float32)
    vertex_normals = np.empty((index.shape[0], 3), np.float32)

    def gather_piece(rows: slice) -> None:  # mode="wrap" writes `out` unbuffered; -1 (no vn) is zeroed below
        np.take(unit, index[rows], axis=0, out=vertex_normals[rows], mode="wrap")

    each(gather_piece, pieces(index.shape[0], _CROSS_CHUNK))
    if ok.all() and index.min() >= 0:  # the usual case: nothing to derive
        return vertex_normals, np.zeros(rows, dtype=bool)
    missing = (index < 0) | ~ok[index]
    vertex_normals[missing] = 0.0
    return vertex_normals, missing


def _fill_vertex_normals(vertex_normals: np.ndarray, missing: np.ndarray, shape: _Shape,
                         row_vertex: np.ndarray | None) -> np.ndarray:
    """Normals for the missing rows: the normalised sum of the unit normals of the faces around the
    row's position (zero-area faces, still zero here, do not count). Returns the rows still missing
    one: their position touches no face with an area."""
    sums = _normal_sums(shape.face_normals, shape.corner_vertex, shape.face_start, shape.sizes,
                        shape.positions.shape[0])
    if missing.all() and row_vertex is None:  # no `vn` in the file, the usual case: straight into place
        return ~unit_rows(sums, out=vertex_normals)[1]
    # In the rows' type: a fancy assignment that also converts is slower than a gather of the right type.
    position_normals, position_ok = unit_rows(sums, vertex_normals.dtype)
    if missing.all():  # no vn, rows per corner: each takes its position's normal
        np.take(position_normals, row_vertex, axis=0, out=vertex_normals)
        return ~position_ok[row_vertex]
    rows = np.flatnonzero(missing)
    vertices = _positions_of(rows, row_vertex)
    vertex_normals[rows] = position_normals[vertices]
    still = np.zeros_like(missing)
    still[rows] = ~position_ok[vertices]
    return still


def _normal_sums(face_normals: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray, sizes: np.ndarray,
                 vertex_count: int) -> np.ndarray:
    """(V, 3): per position, the sum of the normals of the faces that use it, corner by corner in order."""
    compiled = _compiled_loops(face_normals, corner_vertex, face_start)
    if compiled is not None:
        return _compiled_normal_sums(compiled, face_normals, corner_vertex, face_start, vertex_count)
    sums = np.zeros((3, vertex_count))
    # Polygons of one size go in blocks of whole polygons, so that each normal is repeated a fixed number
    # of times (numpy's quick case); else by each polygon's corners in the block.
    size = int(sizes[0]) if _one_small_size(sizes) else None
    block_corners = _CORNER_BLOCK if size is None else max(size, _CORNER_BLOCK // size * size)
    for block in pieces(corner_vertex.size, block_corners):
        polygons, counts = (_polygons_in(face_start, sizes, block.start, block.stop) if size is None
                            else (slice(block.start // size, block.stop // size), size))
        rows = corner_vertex[block].astype(np.intp)  # numpy's own index type, once for the three axes
        for axis in range(3):  # an axis at a time: contiguous values add faster
            _sums_at(sums[axis], rows, np.repeat(face_normals[polygons, axis], counts))
    return sums.T


def _compiled_normal_sums(compiled: ModuleType, face_normals: np.ndarray, corner_vertex: np.ndarray,
                          face_start: np.ndarray, vertex_count: int) -> np.ndarray:
    """_normal_sums's outcome by the compiled loop: a range of positions per thread, each reading every corner."""
    sums = np.zeros((vertex_count, 3))
    each(lambda rows: compiled.normal_sums(face_normals, corner_vertex, face_start, rows.start, rows.stop, sums),
         one_per_thread(vertex_count))
    return sums


# Where the bounding-box texture's u and v run, by the box's flattest axis, reversed or not: upright as
# seen from that axis's positive side with y up, and a floor as the start camera sees it from above.
UPRIGHT_FROM: dict[int, tuple[list[int], np.ndarray]] = {
    0: ([2, 1], np.array([True, False])),  # a wall facing x: u along -z, v up y
    1: ([0, 2], np.array([False, True])),  # a floor: u along x, v along -z, away from the start camera
    2: ([0, 1], np.array([False, False])),  # facing the start camera: u along x, v up y
}
_CORNER_BLOCK = 1 << 16  # corners whose face normals are repeated at once


def _polygons_in(face_start: np.ndarray, sizes: np.ndarray, first: int, stop: int) -> tuple[slice, np.ndarray]:
    """The polygons that corners `first` to `stop` belong to, and how many of those corners each holds."""
    low, high = polygons_of_corners(face_start, np.array([first, stop - 1]))
    counts = sizes[low:high + 1].copy()
    counts[0] -= first - face_start[low]  # the first and last polygons' corners outside the range
    counts[-1] -= face_start[high + 1] - stop
    return slice(low, high + 1), counts


def _sums_at(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """out[rows[i]] += values[i], in the order of i: np.bincount's sums, bit for bit, without its
    two passes over the rows to find their range (these are in range), and into the sums so far."""
    np.add.at(out, rows, values)


def _fill_degenerate(shape: _Shape, vertex_normals: np.ndarray, row_vertex: np.ndarray | None) -> None:
    """A zero-area face takes the average of its corners' normals, or +z when that is zero too."""
    faces = np.flatnonzero(shape.degenerate)
    sizes = shape.sizes[faces]
    corners = corners_of_polygons(shape.face_start[faces], sizes)
    rows = shape.corner_vertex[corners] if row_vertex is None else corners  # per position: the corner's position
    sums = np.add.reduceat(vertex_normals[rows], np.concatenate(([0], np.cumsum(sizes)[:-1])), axis=0)
    averaged, ok = unit_rows(sums)
    averaged[~ok] = FALLBACK_NORMAL
    shape.face_normals[faces] = averaged


# Extents this share of the largest apart are equal: a cube written in float32 is 2 by 2 by 2.000001.
EQUAL_EXTENT_SHARE = 1e-5


def _flattest_axis(extent: np.ndarray) -> int:
    """The axis of the box's least extent; of equal ones, z first, then y (facing the start camera)."""
    least = extent <= extent.min() + EQUAL_EXTENT_SHARE * extent.max()
    return int(np.flatnonzero(least)[-1])


def _bounding_box_uv(positions: np.ndarray, vertices: np.ndarray | None,
                     bounds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Planar projection onto the bounding box's two largest extents, each mapped to 0..1, for these
    positions (None: every position, in order), reading upright from the box's flattest side."""
    low, high = bounds
    with np.errstate(all="ignore"):
        extent = high - low
        extent = np.where(np.isfinite(extent), extent, 0.0)
    flattest = _flattest_axis(extent)
    axes, reversed_axes = UPRIGHT_FROM[flattest]
    flat = extent[axes] <= 0
    scale = np.where(flat, 1.0, extent[axes])
    start = np.where(reversed_axes, high[axes], low[axes])  # a reversed axis counts down from its high side
    # Per position, then gathered: a position has one box coordinate, and corners outnumber positions.
    uv = np.empty((positions.shape[0], 2), np.float32)

    def piece(rows: slice) -> None:
        with np.errstate(all="ignore"):
            block = positions[rows][:, axes] - start
            block /= scale
        block[:, reversed_axes] = 0.0 - block[:, reversed_axes]  # not * -1: no -0.0 at the high side
        block[:, flat] = 0.0
        block[~np.isfinite(block)] = 0.0
        uv[rows] = block

    each(piece, pieces(positions.shape[0]))
    return uv if vertices is None else gathered(uv, vertices)
