"""Readers for the files a person gives the viewer: OBJ models and texture images."""

from app.loaders.image import fallback_texture, load_image, load_texture_or_fallback
from app.loaders.obj import build_mesh, load_obj, parse_obj

__all__ = ["build_mesh", "fallback_texture", "load_image", "load_obj", "load_texture_or_fallback", "parse_obj"]
