"""Small geometric helpers, one copy each: unit vectors, polygon normals, bounds, equal rows merged."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from marraztu.model.threads import each, gathered, pieces

# The GPU draws in float32: a coordinate beyond this would be infinite there.
FLOAT32_MAX = float(np.finfo(np.float32).max)


# The farthest coordinate a model may have: the GPU lights in float32, and a vector's squared length
# must stay below float32's largest number with the camera a few times the model's size away.
DRAWABLE_COORDINATE = 1e18
# The smallest model: framed, its vectors' squared lengths must stay above float32's smallest normal
# number (1.2e-38), under which the GPU lights it flat or not at all. A point, of no size, is drawn as one.
DRAWABLE_SIZE = 1e-18
# Where a light lit from its place may stand: from there the vector to a model's point (within
# DRAWABLE_COORDINATE) squares within float32, as the GPU lights; a bulb at 1e20 lit nothing.
LIGHT_REACH = 5e18
# Where a camera's body and its eye may stand: the vector from there to a model's point, a light or
# another camera's body (each within its own reach) is 1e19 long at most along an axis, 3e38 squared.
CAMERA_REACH = 5e18


@dataclass(frozen=True)
class Reach:
    """How far from the origin, along an axis, an element of one kind may stand, and the words of every
    refusal that says so: what the GPU's 32-bit numbers cannot do with one past it, and what it is."""

    most: float
    cannot: str  # "light" a model, "see from" a camera
    what: str


MODELS_REACH = Reach(DRAWABLE_COORDINATE, "light", "the model")
CAMERAS_REACH = Reach(CAMERA_REACH, "see from", "the camera")


def cannot_light(low: np.ndarray, high: np.ndarray) -> str | None:
    """Why a model within these bounds cannot be lit (a coordinate past DRAWABLE_COORDINATE, or a size
    under DRAWABLE_SIZE); None if it can."""
    farthest, size = (float(value) for value in _reach_and_size(np.asarray(low), np.asarray(high)))
    return lighting_refusal(farthest, size)


def lighting_refusal(farthest: float, size: float, reach: Reach = MODELS_REACH,
                     remedy: str = "scale it down") -> str | None:
    """Why an element of this reach's kind, reaching `farthest` from the origin along an axis and `size`
    across, cannot be drawn; None if it can."""
    if farthest > reach.most:
        return (f"a coordinate reaches {_shown_beside(farthest, reach.most)}: past {reach.most:.0e} the GPU's "
                f"32-bit numbers cannot {reach.cannot} {reach.what} ({remedy})")
    if 0.0 < size < DRAWABLE_SIZE:
        return (f"{reach.what} is {_shown_beside(size, DRAWABLE_SIZE)} across: under {DRAWABLE_SIZE:.0e} the "
                f"GPU's 32-bit numbers cannot light {reach.what} (scale it up)")
    return None


def _shown_beside(value: float, limit: float) -> str:
    """`value` in three digits, or as many more as keep it on its side of `limit`: three round a value
    just past the limit onto it, which then reads as refused itself."""
    for digits in range(3, 17):
        text = f"{value:.{digits}g}"
        if float(text) != limit and (float(text) > limit) == (value > limit):
            return text
    return f"{value:.17g}"  # seventeen digits give any float back


def all_lightable(farthest: np.ndarray, size: np.ndarray, reach: np.ndarray) -> bool:
    """Whether lighting_refusal finds nothing in any of these, (N,) each, in one pass."""
    return bool((farthest <= reach).all() and not ((size > 0.0) & (size < DRAWABLE_SIZE)).any())


def _reach_and_size(low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """How far from the origin each box reaches along an axis, and its largest side."""
    return np.maximum(-low.min(axis=-1), high.max(axis=-1)), (high - low).max(axis=-1)


def segment_meets_box(origin: np.ndarray, direction: np.ndarray, low: np.ndarray, high: np.ndarray) -> bool:
    """Whether origin + t direction, t in 0..1, meets the box low..high (the slab test), the box grown by
    a billionth of its size or of its distance from the origin, the larger (what rounding may move a
    point by), so that a surface lying on its side (a floor: a box 0 high) is met."""
    pad = 1e-9 * max(float(np.max(high - low)), float(np.max(np.abs(low))), float(np.max(np.abs(high))))
    low, high = low - pad, high + pad
    along = direction != 0.0
    if not ((low <= origin) & (origin <= high))[~along].all():  # parallel to a slab and outside it
        return False
    with np.errstate(over="ignore"):  # a nearly parallel slab: t far off either way, as it should be
        ends = (np.stack([low, high])[:, along] - origin[along]) / direction[along]
    enter, leave = float(np.max(ends.min(axis=0), initial=0.0)), float(np.min(ends.max(axis=0), initial=1.0))
    return max(enter, 0.0) <= min(leave, 1.0)


def holds_in_float32(table: np.ndarray) -> bool:
    """Whether every number is finite and within float32's range, as the GPU holds it. Two reductions,
    no mask as large as the table; NaN fails both comparisons."""
    return bool(table.max(initial=0.0) <= FLOAT32_MAX and table.min(initial=0.0) >= -FLOAT32_MAX)


def unit(vector: Iterable[float]) -> np.ndarray:
    """The vector scaled to length 1; a zero vector stays zero."""
    v = np.asarray(vector, float)
    length = float(np.linalg.norm(v))
    return v / length if length > 0.0 else v


def unit_or_none(vector: Iterable[float], shortest: float = 1e-12) -> np.ndarray | None:
    """The vector scaled to length 1, or None when it is too short to have a direction."""
    v = np.asarray(vector, float)
    length = float(np.linalg.norm(v))
    return None if length < shortest else v / length


def unit_rows(vectors: np.ndarray, dtype: type = np.float64, out: np.ndarray | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
    """Each row scaled to length 1 and stored as `dtype` (or into `out`, in its type), and which rows
    could be; the others are left zero. In pieces of rows on threads, each row's arithmetic as in one piece."""
    scaled = np.empty(vectors.shape, dtype) if out is None else out
    ok = np.empty(vectors.shape[0], bool)

    def piece(rows: slice) -> None:
        block, usable = vectors[rows], ok[rows]
        with np.errstate(all="ignore"):
            length = np.sqrt(np.einsum("ij,ij->i", block, block))
            np.logical_and(np.isfinite(length), length > 1e-300, out=usable)
            scaled[rows] = block / np.where(usable, length, 1.0)[:, None]
        scaled[rows][~usable] = 0.0

    each(piece, pieces(vectors.shape[0]))
    return scaled, ok


def newell_normal(points: np.ndarray) -> np.ndarray:
    """A polygon's normal, not normalised, by Newell's method: right even for a slightly bent polygon."""
    following = np.roll(points, -1, axis=0)
    return np.cross(points, following).sum(axis=0)


def column_bounds(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(low, high): each column's minimum and maximum of an (N, k) table, N > 0.

    Whole columns on one thread: pieces may pick the other of 0.0 and -0.0, whose sign the
    bounding-box uvs carry."""
    # Column by column: reducing a C-ordered table over axis 0 runs its inner loop across short rows.
    low = np.array([table[:, column].min() for column in range(table.shape[1])])
    high = np.array([table[:, column].max() for column in range(table.shape[1])])
    return low, high


# Odd 64-bit constants (from splitmix64 and xxhash) that spread each coordinate's bits over the key.
_ROW_KEY_FACTORS = np.array([0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9], np.uint64)


def merged_rows(table: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows, first, inverse) of an (N, 3) float64 table of finite numbers: its distinct rows in the
    order first seen, the index of each one's first appearance, and each row's index among them.

    Not np.unique(axis=0), which sorts 24-byte records several times more slowly, and not trimesh's
    unique_rows, which rounds: rows are hashed to one 64-bit key, whose low bits then hold the row's
    index, so that a plain sort (quicker than an argsort) groups them; the rare key shared by
    different rows is caught, and np.unique groups the rows of those keys alone."""
    if table.ndim != 2 or table.shape[1] != 3:
        raise ValueError(f"merged_rows takes rows of three numbers, not shape {table.shape}")
    if len(table) == 0:
        return table, np.zeros(0, np.int64), np.zeros(0, np.int64)
    first, group = _groups_by_key(table)
    differ = _differing_from_first(table, first, group)
    if differ.size:  # keys collided
        first, group = _collisions_split(table, first, group, np.unique(group[differ]))
    # The groups in the order the table first shows them: a group's number is its first row's rank.
    is_first = np.zeros(len(table), bool)
    is_first[first] = True
    number = (np.cumsum(is_first) - 1)[first]
    first = np.flatnonzero(is_first)
    return gathered(table, first), first, gathered(number, group)


def _groups_by_key(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows grouped by key: each group's first row, and each row's group. The key's low bits give way
    to the row's index, so sorting the keys orders each group's rows by index too."""
    count = len(table)
    index_bits = np.uint64(max(1, (count - 1).bit_length()))
    keyed = _row_keys(table, index_bits)
    keyed.sort()
    order, starts = _split_keys(keyed, index_bits)
    del keyed
    sorted_group = np.repeat(np.arange(len(starts)), np.diff(np.append(starts, count)))
    group = np.empty(count, np.int64)

    def scatter(rows: slice) -> None:  # each row's place once: the pieces write apart
        group[order[rows]] = sorted_group[rows]

    each(scatter, pieces(count))
    return order[starts], group


def _split_keys(keyed: np.ndarray, index_bits: np.uint64) -> tuple[np.ndarray, np.ndarray]:
    """Of sorted keys, one at least: each one's row index (its low bits), and where each run of one key
    (its other bits) starts."""
    order, starts_run = np.empty(len(keyed), np.int64), np.empty(len(keyed), bool)
    starts_run[0] = True
    index_mask = (np.uint64(1) << index_bits) - np.uint64(1)

    def piece(rows: slice) -> None:  # reads a row before its own, which no piece writes
        order[rows] = keyed[rows] & index_mask
        low = max(rows.start, 1)
        np.not_equal(keyed[low:rows.stop] >> index_bits, keyed[low - 1:rows.stop - 1] >> index_bits,
                     out=starts_run[low:rows.stop])

    each(piece, pieces(len(keyed)))
    return order, np.flatnonzero(starts_run)


def _collisions_split(table: np.ndarray, first: np.ndarray, group: np.ndarray, collided: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """`first` and `group` with the groups `collided` (which hold different rows under one key)
    regrouped by np.unique, their rows alone: equal rows have equal keys, so no other group holds
    one of theirs."""
    rows = np.flatnonzero(np.isin(group, collided))
    _, row_first, row_group = np.unique(table[rows], axis=0, return_index=True, return_inverse=True)
    kept = np.ones(len(first), bool)
    kept[collided] = False
    renumbered = np.cumsum(kept) - 1  # the groups kept, numbered again from 0
    group = renumbered[group]
    group[rows] = int(kept.sum()) + row_group.reshape(-1)
    return np.concatenate([first[kept], rows[row_first]]), group


def _differing_from_first(table: np.ndarray, first: np.ndarray, group: np.ndarray) -> np.ndarray:
    """The rows that differ from their group's first row: where different rows share a key."""
    firsts = gathered(table, first)

    def piece(rows: slice) -> np.ndarray:
        same = np.take(firsts, group[rows], axis=0) == table[rows]
        return rows.start + np.flatnonzero(~(same[:, 0] & same[:, 1] & same[:, 2]))

    return np.concatenate(each(piece, pieces(len(table))))


def _row_keys(table: np.ndarray, index_bits: np.uint64) -> np.ndarray:
    """One 64-bit key per row of an (N, 3) float64 table, from the numbers' bits, its low `index_bits`
    bits given to the row's index. Each number is folded onto its low bits first: a float32 number held
    as a double has 29 zero bits there, which a product alone would keep."""
    key = np.empty(len(table), np.uint64)

    def piece(piece_rows: slice) -> None:
        rows, out = table[piece_rows], key[piece_rows]
        number = np.empty(len(rows), np.float64)
        bits, folded = number.view(np.uint64), np.empty(len(rows), np.uint64)
        out[:] = 0
        for column, factor in enumerate(_ROW_KEY_FACTORS):
            np.add(rows[:, column], 0.0, out=number)  # -0.0 becomes 0.0: equal numbers, equal bits
            np.right_shift(bits, np.uint64(29), out=folded)
            folded ^= bits
            folded *= factor
            out += folded
        out ^= out >> np.uint64(32)
        out >>= index_bits
        out <<= index_bits
        out |= np.arange(piece_rows.start, piece_rows.stop, dtype=np.uint64)

    each(piece, pieces(len(table)))
    return key
