"""Which box holds which: for each of many boxes, the first of many others that holds it whole.

A pairwise look costs the product of the two counts (thousands of models loaded at once against the
scene); numpy has no spatial index, so the holders are sorted into grids of cells as large as they are,
where a box looks only in the few cells a holder of it can start in, each in the holders' order."""

from __future__ import annotations

import numpy as np

SUBDIVISION_BITS = 1  # a level's cells are half as wide as its boxes may be long
_LEAST_EXPONENT = -1074  # of the least float above 0: no cell is narrower
_PAIRWISE_BLOCK = 1 << 20  # box pairs compared at once where boxes are not finite
# Pair by pair below these: a grid costs some ten to twenty pairs a holder to build, so a few boxes,
# or a few hundred against as many, are compared faster each with every holder.
GRID_FROM_PAIRS = 1 << 16
GRID_FROM_BOXES = 10


def holds(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """Whether each holder box holds the box beside it (broadcast) whole, each side within."""
    return ((holder_low <= low) & (holder_high >= high)).all(axis=-1)


def first_holders(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray,
                  itself: np.ndarray) -> np.ndarray:
    """(N,) for each box (low, high), the index of the first of the holder boxes that holds it whole,
    never its own (`itself`: its index among the holders, or -1); -1 where none does."""
    none = len(holder_low)
    best = np.full(len(low), none, dtype=np.int64)
    if not len(low) or not none:
        return np.full(len(low), -1, dtype=np.int64)
    if len(low) < GRID_FROM_BOXES or len(low) * none < GRID_FROM_PAIRS:  # a model added among the scene's
        _pairwise(holder_low, holder_high, low, high, itself, np.arange(none), np.arange(len(low)), best)
        return np.where(best == none, -1, best)
    holder_finite, finite = _finite_boxes(holder_low, holder_high), _finite_boxes(low, high)
    # A scene that was checked holds no box that is not finite: those few are looked at pair by pair.
    _pairwise(holder_low, holder_high, low, high, itself, np.flatnonzero(~holder_finite), np.arange(len(low)), best)
    _pairwise(holder_low, holder_high, low, high, itself, np.flatnonzero(holder_finite), np.flatnonzero(~finite), best)
    _gridded(holder_low, holder_high, low, high, itself, np.flatnonzero(holder_finite), np.flatnonzero(finite), best)
    return np.where(best == none, -1, best)


def _finite_boxes(low: np.ndarray, high: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore", over="ignore"):
        return np.isfinite(high - low).all(axis=1)  # inf - inf is nan: both sides finite


def _pairwise(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray,
              itself: np.ndarray, holders: np.ndarray, boxes: np.ndarray, best: np.ndarray) -> None:
    """Lowers `best` for `boxes` to the first of `holders` (indices, in order) holding each."""
    if not len(holders) or not len(boxes):
        return
    step = max(1, _PAIRWISE_BLOCK // len(holders))
    for first in range(0, len(boxes), step):
        block = boxes[first:first + step]
        held = holds(holder_low[holders], holder_high[holders], low[block, None], high[block, None])
        held &= holders != itself[block, None]
        found = np.where(held.any(axis=1), holders[held.argmax(axis=1)], len(holder_low))
        best[block] = np.minimum(best[block], found)


def _gridded(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray,
             itself: np.ndarray, holders: np.ndarray, boxes: np.ndarray, best: np.ndarray) -> None:
    """Lowers `best` for `boxes` to the first of `holders` (finite, as are the boxes) holding each."""
    if not len(holders) or not len(boxes):
        return
    holder_sides = holder_high[holders] - holder_low[holders]
    longest = (high[boxes] - low[boxes]).max(axis=1)
    least = _least_level(np.concatenate([holder_sides.max(axis=1), longest]))
    holder_levels, box_levels = _levels(holder_sides.max(axis=1), least), _levels(longest, least)
    lists: list[np.ndarray] = []
    units: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    listed = 0
    for level in np.unique(holder_levels).tolist():
        on_level = np.flatnonzero(holder_levels == level)
        asking = np.flatnonzero(box_levels <= level)  # a holder is as long as what it holds on every side
        if not asking.size:
            continue
        width = np.ldexp(1.0, max(level - SUBDIVISION_BITS, _LEAST_EXPONENT))
        cells = _cells(holder_low[holders[on_level]], width)
        order = np.lexsort((on_level, *cells.T[::-1]))  # by cell, and in each cell in the holders' order
        asked, asker = _cells_asked(low[boxes[asking]], high[boxes[asking]], width,
                                    _spans(holder_sides[on_level].max(axis=0), width))
        row, start, end = _lists_in_cells(cells[order], asked)
        lists.append(holders[on_level[order]])
        units.append((boxes[asking[asker[row]]], start + listed, end + listed))
        listed += len(on_level)
    if units:
        unit_box, start, end = (np.concatenate(column) for column in zip(*units))
        _scan(holder_low, holder_high, low, high, itself, np.concatenate(lists), unit_box, start, end, best)


def _levels(longest: np.ndarray, least: int) -> np.ndarray:
    """Each box's level: the power of two above its longest side, so that a box holding another is on
    its level or above; `least` for a box with no extent, which then sits among the smallest."""
    return np.where(longest > 0.0, np.frexp(longest)[1].astype(np.int64), least)


def _least_level(longest: np.ndarray) -> int:
    """The least level of the boxes that have an extent (0 where none has)."""
    sized = longest[longest > 0.0]
    return int(np.frexp(sized)[1].min()) if sized.size else 0


def _cells(corners: np.ndarray, width: float) -> np.ndarray:
    """(N, 3) the cell of a grid `width` wide (a power of two) that each corner lies in: dividing by a
    power of two is exact where it neither overflows nor underflows, and rounding keeps the order where
    it does."""
    with np.errstate(over="ignore", under="ignore"):
        return np.floor(corners / width) + 0.0  # + 0.0: -0.0 is the cell 0


def _spans(sides: np.ndarray, width: float) -> np.ndarray:
    """(3,) along each axis, how many cells `width` wide a least corner of one of these holders may lie
    below the least corner of a box it holds: the power of two above their longest side there, in cells."""
    exponent = int(np.frexp(width)[1]) - 1
    sized = sides > 0.0  # a flat side's 2 ** (1 - exponent) would overflow where cells are under 2 ** -1023
    spans = np.zeros(len(sides))
    spans[sized] = np.exp2(np.maximum(np.frexp(sides[sized])[1] - exponent, 0))  # each side < 2 ** (exponent + its)
    return spans


def _cells_asked(low: np.ndarray, high: np.ndarray, width: float, spans: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """The cells where a holder of each box may have its least corner, and the box of each: a holder
    reaching over the box's high side and shorter than `spans` cells starts less than that below it
    (one cell more where a division may have underflowed), and starts no higher than the box's low side."""
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        above, below = high / width, low / width
        highest = np.floor(below) + 0.0
        lowest = np.floor(above) - spans - (np.abs(above) < 1.0)
        counts = highest - lowest + 1.0  # not a number where both are the same infinity: that one cell
        counts = np.where(np.isnan(counts), 1.0, np.clip(counts, 0.0, spans + 2.0)).astype(np.int64)
    per_box = counts.prod(axis=1)
    box = np.repeat(np.arange(len(low)), per_box)
    step = np.arange(len(box)) - np.repeat(np.cumsum(per_box) - per_box, per_box)
    steps = np.empty((len(box), 3))
    for axis in (2, 1, 0):  # counted down from the highest cell: above 2 ** 53 cells, only those are floats
        steps[:, axis] = step % counts[box, axis]
        step //= counts[box, axis]
    with np.errstate(invalid="ignore"):
        return highest[box] - steps, box


def _lists_in_cells(sorted_cells: np.ndarray, asked: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each asked cell that holds some of the sorted cells (one level's holders, in order): its
    row among the asked, and where its run starts and ends among the sorted."""
    keys = _cell_keys(np.concatenate([sorted_cells, asked]))
    held, asked_keys = keys[:len(sorted_cells)], keys[len(sorted_cells):]
    runs, run_starts = np.unique(held, return_index=True)  # sorted by cell, so each cell one run
    run_ends = np.append(run_starts[1:], len(held))
    at = np.minimum(np.searchsorted(runs, asked_keys), len(runs) - 1)
    rows = np.flatnonzero(runs[at] == asked_keys)
    return rows, run_starts[at[rows]], run_ends[at[rows]]


def _cell_keys(cells: np.ndarray) -> np.ndarray:
    """One integer a cell, equal where the cells are, from each axis's rank (three floats in one)."""
    ranks = [np.unique(column, return_inverse=True)[1].astype(np.int64) for column in cells.T]
    count = len(cells) + 1
    plane = np.unique(ranks[0] * count + ranks[1], return_inverse=True)[1].astype(np.int64)
    return plane * count + ranks[2]


def _scan(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray, itself: np.ndarray,
          holders: np.ndarray, unit_box: np.ndarray, start: np.ndarray, end: np.ndarray, best: np.ndarray) -> None:
    """Walks each list (`holders[start:end]`, in the holders' order) for its box until a holder holds
    it, or the list is done, or the rest come after one found in another list: each round takes twice
    as many from each list as the last, so a list is looked at no more than twice as far as needed."""
    width = 1
    while len(unit_box):
        taken = np.minimum(end - start, width)
        unit = np.repeat(np.arange(len(unit_box)), taken)
        offsets = np.arange(len(unit)) - np.repeat(np.cumsum(taken) - taken, taken)
        holder, box = holders[start[unit] + offsets], unit_box[unit]
        held = holds(holder_low[holder], holder_high[holder], low[box], high[box]) & (holder != itself[box])
        firsts = np.minimum.reduceat(np.where(held, holder, len(holder_low)), np.cumsum(taken) - taken)
        np.minimum.at(best, unit_box, firsts)
        start = start + taken
        going = (firsts == len(holder_low)) & (start < end)
        going[going] = holders[start[going]] < best[unit_box[going]]
        unit_box, start, end, width = unit_box[going], start[going], end[going], width * 2
