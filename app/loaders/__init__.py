"""Readers for the files a person gives the viewer: models (marraztu.loaders.registry), images, scene files."""
