"""Readers for the files a person gives the viewer: models (registry.py), images, scene files."""
