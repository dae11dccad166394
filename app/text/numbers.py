"""How the panels write their numbers so that a model a centimetre across does not read as all
zeros: positions with the decimals its size needs, a matrix entry too small for its decimals in
powers of ten."""

from __future__ import annotations

import math

import numpy as np

SIGNIFICANT_DIGITS = 3  # of a model's size, that a position on it shows
MOST_DECIMALS = 15  # as far as a 64-bit number's digits go
NOISE_SHARE = 1e-9  # of a matrix column's largest entry: below it, an entry is rounding


def position_decimals(size: float, least: int) -> int:
    """Decimals for positions on a model `size` across: at least `least`, enough for its size's first
    SIGNIFICANT_DIGITS digits."""
    if not size > 0.0 or not math.isfinite(size):
        return least
    needed = SIGNIFICANT_DIGITS - 1 - math.floor(math.log10(size))
    return max(least, min(needed, MOST_DECIMALS))


def matrix_entries(matrix: np.ndarray, decimals: int) -> list[list[str]]:
    """A matrix's entries with `decimals` decimals, or, where those would leave one less than two
    digits (under 0.01 at three decimals), as 6.4e-4: the matrix of a model in millimetres must still
    give the numbers printed under it. An entry a billionth of its column's largest is rounding (a
    quarter turn's cosine) and reads 0; the bottom row, exact in every matrix the panels print, never
    does (a model 1e12 from the origin keeps its 1)."""
    columns = np.abs(matrix).max(axis=0)
    rows = [[_entry(float(value), decimals, float(largest)) for value, largest in zip(row, columns)]
            for row in matrix[:-1]]
    return rows + [[_entry(float(value), decimals, 0.0) for value in matrix[-1]]]


def fixed(value: float, decimals: int) -> str:
    """`value` with `decimals` decimals, never "-0.00": + 0.0 turns a rounded -0.0 into 0.0."""
    return f"{round(value, decimals) + 0.0:.{decimals}f}"


def significant(value: float, digits: int = SIGNIFICANT_DIGITS) -> str:
    """`value` to `digits` significant digits, no zeros after them: 0.299, 412, 5, 1000."""
    return f"{float(f'{value:.{digits}g}'):g}"


def _entry(value: float, decimals: int, largest: float) -> str:
    if abs(value) < NOISE_SHARE * largest:
        value = 0.0
    if value == 0.0 or abs(value) >= 10.0 ** (1 - decimals) or not math.isfinite(value):
        return fixed(value, decimals)
    mantissa, power = f"{value:.1e}".split("e")
    return f"{mantissa}e{int(power)}"


def aligned_columns(entries: list[list[str]], least: int) -> list[str]:
    """Rows of a matrix's entries, each column right-aligned to its widest entry (at least `least`
    wide): a translation of 1e12 widens its own column, where it pushed its row's later entries out
    of line with the rows above and below."""
    widths = [max(least, *(len(row[k]) for row in entries)) for k in range(len(entries[0]))]
    return [" ".join(f"{entry:>{width}}" for entry, width in zip(row, widths)) for row in entries]
