"""marraztu: a 3D viewer for people who learn and teach computer graphics."""

from pathlib import Path

PROJECT_ROOT = Path(__file__).resolve().parent.parent
SHADER_DIR = PROJECT_ROOT / "shaders"
ASSET_DIR = PROJECT_ROOT / "assets"
