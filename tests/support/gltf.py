"""GLB files made in tests from a glTF JSON and its binary chunk."""

from __future__ import annotations

import json
import struct
from typing import Any


def glb(document: dict[str, Any], binary: bytes) -> bytes:
    """A GLB of this JSON and binary chunk, each padded to four bytes as glTF's are."""
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks
