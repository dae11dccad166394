"""Which box holds which (Scene.enclosers, said of each start-up load): the first holder of each box is a
plain pairwise look's, at any magnitude, and found comparing each box with a few near it, not with all."""

from __future__ import annotations

import warnings
from collections.abc import Iterator

import numpy as np
import pytest

from marraztu.loaders.scenefile import DEFAULT_MATERIAL, empty_scene
from marraztu.model import holders
from marraztu.model.build import build_mesh
from marraztu.model.holders import first_holders
from marraztu.model.scene import SceneObject, world_boxes
from marraztu.model.transforms import placement

CUBE_FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
Boxes = tuple[np.ndarray, np.ndarray]


def pairwise(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray,
             itself: np.ndarray) -> np.ndarray:
    with np.errstate(invalid="ignore"):
        held = ((holder_low <= low[:, None]) & (holder_high >= high[:, None])).all(axis=2)
    held &= np.arange(len(holder_low)) != itself[:, None]
    return np.where(held.any(axis=1), held.argmax(axis=1), -1)


def layout(kind: str, count: int, rng: np.random.Generator) -> Boxes:
    """(low, high) of `count` boxes laid out as `kind` says."""
    if kind == "scattered":  # as many to a room whatever their number
        side = 2.0 * count ** (1 / 3)
        centres, halves = rng.uniform(-side, side, (count, 3)), rng.uniform(0.1, 3.0, (count, 1))
        return centres - halves, centres + halves
    if kind == "nested":  # each inside the larger ones, in no order
        halves = rng.permutation(np.arange(1.0, count + 1.0))[:, None] * rng.uniform(0.9, 1.1, (count, 3))
        return -halves, halves
    if kind == "alike":  # the same file many times
        return np.zeros((count, 3)), np.ones((count, 3))
    if kind == "meeting":  # whole numbers: faces meet, boxes match exactly, some flat
        low = rng.integers(-3, 3, (count, 3)).astype(float)
        return low, low + rng.choice([0.0, 1.0, 2.0, 4.0], (count, 3))
    if kind == "any magnitude":  # 1e-300 to 1e300 across, some points, some sides overflowing
        centres = rng.normal(size=(count, 3)) * 10.0 ** rng.integers(-300, 300, (count, 1))
        halves = np.abs(rng.normal(size=(count, 3))) * 10.0 ** rng.integers(-320, 308, (count, 1))
        halves[rng.random(count) < 0.2] = 0.0
        with np.errstate(over="ignore"):
            return centres - halves, centres + halves
    if kind == "far and small":  # cells past 2 ** 53 from the origin, where floats are whole numbers
        low = 1e18 * rng.choice([1.0, -1.0, 3.0], (count, 1)) + rng.integers(-3, 3, (count, 3)) * 128.0
        high = low + rng.choice([0.0, 128.0, 256.0, 512.0], (count, 3))
        small = rng.random(count) < 0.2
        low[small] = rng.uniform(-1.0, 1.0, (small.sum(), 3))
        high[small] = low[small] + 1e-3
        return low, high
    low, high = layout("meeting", count, rng)  # not finite: set by hand, never in a checked scene
    for sides in (low, high):
        spoilt = rng.random((count, 3)) < 0.05
        sides[spoilt] = rng.choice([-np.inf, np.inf, np.nan], spoilt.sum())
    return low, high


def grid_always(monkeypatch: pytest.MonkeyPatch) -> None:
    """The grid for any number of boxes, where a few would be compared pair by pair."""
    monkeypatch.setattr(holders, "GRID_FROM_PAIRS", 0)
    monkeypatch.setattr(holders, "GRID_FROM_BOXES", 0)


KINDS = ["scattered", "nested", "alike", "meeting", "any magnitude", "far and small", "not finite"]


@pytest.mark.parametrize("kind", KINDS)
def test_first_holders_are_a_pairwise_looks(kind: str, monkeypatch: pytest.MonkeyPatch) -> None:
    grid_always(monkeypatch)  # the grid's answers, not the pairwise look's own
    rng = np.random.default_rng(KINDS.index(kind))
    for _ in range(30):
        holder_low, holder_high = layout(kind, int(rng.integers(1, 200)), rng)
        if rng.random() < 0.5:  # the holders themselves, as the start-up's loads are shown
            picked = rng.integers(0, len(holder_low), int(rng.integers(1, 200)))
            low, high = holder_low[picked], holder_high[picked]
            itself = np.where(rng.random(len(picked)) < 0.8, picked, -1)
        else:
            low, high = layout(kind, int(rng.integers(1, 200)), rng)
            itself = np.full(len(low), -1)
        expected = pairwise(holder_low, holder_high, low, high, itself)
        assert np.array_equal(first_holders(holder_low, holder_high, low, high, itself), expected)


@pytest.fixture
def compared(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[int]]:
    """Counts the box pairs compared."""
    counted = [0]
    real = holders.holds

    def counting(holder_low: np.ndarray, holder_high: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
        counted[0] += np.broadcast(holder_low, low).size // 3
        return real(holder_low, holder_high, low, high)

    monkeypatch.setattr(holders, "holds", counting)
    yield counted


@pytest.mark.parametrize("kind", ["scattered", "nested", "alike"])
@pytest.mark.parametrize("count", [600, 4000])
def test_the_enclosers_of_thousands_of_loads_compare_each_with_a_few_boxes(compared: list[int], kind: str,
                                                                           count: int) -> None:
    """Each start-up load was compared with every shown box, in blocks: twice the files on the command
    line took four times as long to tell. Now each looks in the few cells where a holder of it can start."""
    cube = build_mesh("cube", np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)]),
                      CUBE_FACES)
    low, high = layout(kind, count, np.random.default_rng(count))
    scene = empty_scene()
    for index, (least, most) in enumerate(zip(low, high)):
        model = placement(tuple((least + most) / 2.0), (0.0, 0.0, 0.0))
        model[:3, :3] = np.diag((most - least) / 2.0)
        scene.objects.append(SceneObject(f"o{index}", cube, DEFAULT_MATERIAL, [model]))
    found = scene.enclosers(scene.objects)
    assert compared[0] <= 30 * count, compared
    corners = world_boxes(scene.shown_elements())
    expected = pairwise(corners.min(axis=1), corners.max(axis=1), corners.min(axis=1), corners.max(axis=1),
                        np.arange(count))
    assert [scene.objects.index(holder) if holder is not None else -1 for holder in found] == expected.tolist()
    assert found.count(None) < {"scattered": count, "nested": count // 20, "alike": 1}[kind]  # most held: found early


def test_a_flat_box_narrower_than_the_least_normal_float_is_looked_up_without_a_warning(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The cells a holder may start in were 2 ** (1 - level) along a flat side, then thrown away: past
    2 ** 1023, numpy warned "overflow encountered in exp2" on the terminal (one box 1e-310 x 1e-310 x 0)."""
    grid_always(monkeypatch)
    low, high = np.zeros((2, 3)), np.array([[1e-310, 1e-310, 0.0], [1e-310, 0.0, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        found = first_holders(low, high, low, high, np.arange(2))
    assert found.tolist() == pairwise(low, high, low, high, np.arange(2)).tolist() == [-1, 0]


def test_a_model_added_among_the_scenes_is_compared_pair_by_pair(compared: list[int],
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """add_mesh asks of one box among thousands: building the grid for it cost twenty times the look
    (1.1 ms a call among 1,150 models, the pairwise look 0.05 ms)."""
    monkeypatch.setattr(holders, "_gridded", None)  # not called
    low, high = layout("scattered", 2000, np.random.default_rng(7))
    found = first_holders(low, high, low[:1] + 0.01, high[:1] - 0.01, np.array([-1]))
    assert found.tolist() == [0] and compared[0] == 2000
