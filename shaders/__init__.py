"""The GLSL programs, one file per program (read through marraztu.resources)."""
