"""How many decimals the panels give a position: the seed's one for models of its size, more for
smaller ones, so that a model a centimetre across does not read as all zeros."""

from __future__ import annotations

import math

SIGNIFICANT_DIGITS = 3  # of a model's size, that a position on it shows
MOST_DECIMALS = 15  # as far as a 64-bit number's digits go


def position_decimals(size: float, least: int) -> int:
    """Decimals for positions on a model `size` across: at least `least`, enough for its size's first
    SIGNIFICANT_DIGITS digits."""
    if not size > 0.0 or not math.isfinite(size):
        return least
    needed = SIGNIFICANT_DIGITS - 1 - math.floor(math.log10(size))
    return max(least, min(needed, MOST_DECIMALS))
