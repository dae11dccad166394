"""The MTL file beside an OBJ: the numbers of its first material. Every problem is a note, not an error."""

from __future__ import annotations

from pathlib import Path

from marraztu.loaders.obj.raw import finite_floats


def first_material(base_dir: Path, name: str, notes: list[str]) -> dict[str, object] | None:
    """Ka/Kd/Ks/Ns of the first material in the MTL file next to the OBJ; problems become notes."""
    candidates = [name] + name.split()  # 'mtllib a b.mtl' is one file with a space, or two files
    mtl = next((base_dir / candidate for candidate in candidates if (base_dir / candidate).is_file()), None)
    if mtl is None:
        notes.append(f"material library '{name}' not found next to the model; using the scene's material")
        return None
    try:
        text = mtl.read_bytes()[:16 << 20].decode("utf-8", errors="replace")
    except (OSError, MemoryError) as error:
        notes.append(f"material library '{name}' could not be read ({error}); using the scene's material")
        return None
    material = _parse_first_material(text, name, notes)
    return material or None


def _parse_first_material(text: str, name: str, notes: list[str]) -> dict[str, object]:
    material: dict[str, object] = {}
    inside = False
    for line in text.splitlines():
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            if inside:
                break
            inside = True
        elif inside and key in ("ka", "kd", "ks", "ns"):
            _material_value(material, key, tokens[1:], name, notes)
    if not inside:
        notes.append(f"material library '{name}' defines no material; using the scene's material")
    return material


def _material_value(material: dict[str, object], key: str, tokens: list[str], name: str, notes: list[str]) -> None:
    values = finite_floats(tokens)
    if key == "ns" and values is not None and len(values) == 1:
        material["ns"] = values[0]
    elif key != "ns" and values is not None and len(values) in (1, 3):
        material[key] = tuple(values * 3 if len(values) == 1 else values)  # one number: a grey
    else:
        notes.append(f"material library '{name}': ignored a malformed {key.capitalize()} line")
