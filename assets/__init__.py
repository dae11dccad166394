"""The built-in scene: its models, texture and scene file (read through marraztu.resources)."""
