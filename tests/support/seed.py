"""The seed's own models and Figure 1's check colours, from ../shared (tests skip without them)."""

from __future__ import annotations

from pathlib import Path

import pytest

SEED_ASSETS = Path(__file__).resolve().parents[3] / "shared" / "seed-assets"

SEED_MODELS = [  # name, vertices, faces
    ("x_wing.obj", 3104, 6084),
    ("r_falke.obj", 1885, 3608),
    ("rammer_225.obj", 5518, 5509),
    ("cam.obj", 5, 4),
    ("kupula.obj", 40, 60),
]

SEED_SCENE = """
[materials.shiny_plastic]
ka = [0.0, 0.3, 1.0]
kd = [0.5922, 0.0166, 0.0]
ks = [0.5974, 0.2084, 0.2084]
ns = 100.2237

[materials.greenish]
ka = [0.4, 0.8, 0.3]
kd = [0.3, 0.4, 0.6]
ks = [0.3, 0.1, 0.2]
ns = 60.0

[materials.vibrant_green]
ka = [0.1, 1.0, 0.2]
kd = [0.8, 0.8, 0.8]
ks = [0.5, 0.5, 0.5]
ns = 225.0

[materials.golden]
ka = [0.8, 0.72, 0.0]
kd = [0.8, 0.6, 0.4]
ks = [0.9, 0.8, 0.5]
ns = 80.0

[[cameras]]
model = "{assets}/cam.obj"
position = [0, 0, 150]
material = "shiny_plastic"

[[objects]]
name = "x_wing"
model = "{assets}/x_wing.obj"
position = [-100, 0, 0]
material = "greenish"

[[objects]]
name = "r_falke"
model = "{assets}/r_falke.obj"
position = [100, 0, 0]
material = "vibrant_green"

[[objects]]
name = "Rammer_255"
model = "{assets}/rammer_225.obj"
position = [0, 0, 0]
material = "golden"
"""

EXPECTED = {"x_wing": (80, 60, 76), "r_falke": (20, 75, 51), "golden": (160, 54, 0)}


def seed_model(name: str) -> Path:
    """A seed model's path; the test skips, saying why, where ../shared is absent."""
    path = SEED_ASSETS / name
    if not path.is_file():
        pytest.skip(f"seed assets not available at {SEED_ASSETS}")
    return path
