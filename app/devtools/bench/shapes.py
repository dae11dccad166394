"""5. Inputs shaped to break linear cost: each read in a fresh process, its seconds and peak memory per
megabyte beside a plain model of the same size. A bad file's error must come about as fast as a good
file's model."""

from __future__ import annotations

import base64
import io
import json
import struct
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image

from marraztu.devtools.bench.config import BenchConfig
from marraztu.devtools.bench.loading import peak_rss_bytes
from marraztu.devtools.bench.report import MEGABYTE, markdown_table, number, progress, ratio

SCENE_FILE_MEGABYTES = 8  # under the scene reader's cap on what a scene file may be

SHAPE_HEADERS = ("input", "MB", "outcome", "seconds", "s per MB", "peak RSS MB per MB", "time ÷ plain",
                 "RSS ÷ plain")
_TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n"


@dataclass(frozen=True)
class Shape:
    label: str
    file_name: str
    write: Callable[[Path, int], None]  # (path, bytes wanted)


def _plain(path: Path, size: int) -> None:
    """Triangles of v/vt/vn corners, the way exporters write them."""
    block = "".join(f"v {i}.125 {i}.25 -{i}.5\nvt 0.{i} 0.5\nvn 0 0 1\n" for i in range(1, 4))
    block += "f -3/-3/-3 -2/-2/-2 -1/-1/-1\n"
    path.write_text(_TRIANGLE + block * (size // len(block)))


def _cut_at_the_end(path: Path, size: int) -> None:
    _plain(path, size)
    with path.open("a") as out:
        out.write("f 1/1/1 2/1")  # a corner cut off in the last line


def _one_polygon(path: Path, size: int) -> None:
    corners = size // 24
    with path.open("w") as out:
        out.writelines(f"v {i % 997}.5 {i % 991}.25 0\n" for i in range(corners))
        out.write("f " + " ".join(str(i + 1) for i in range(corners)) + "\n")


def _faces_without_corners(path: Path, size: int) -> None:
    """A bad line on every line: each one the compiled reader leaves to the line reader."""
    path.write_text(_TRIANGLE + "f\n" * (size // 2))


def _materials_in_turn(names: Sequence[str]) -> Callable[[Path, int], None]:
    """A writer of a usemtl before every face, the materials `names` in turn: a run of one face each."""
    block = "".join(f"usemtl {name}\nf 1/1/1 2/1/1 3/1/1\n" for name in names)

    def write(path: Path, size: int) -> None:
        path.write_text(_TRIANGLE + block * (size // len(block)))

    return write


def _ascii_stl(path: Path, size: int) -> None:
    """Facets as exporters write them, over a strip of triangles."""
    facet = ("facet normal 0 0 1\n  outer loop\n" + "    vertex {:.6e} {:.6e} 0\n" * 3
             + "  endloop\nendfacet\n")
    with path.open("w") as out:
        out.write("solid strip\n")
        written, k = 0, 0
        while written < size:
            written += out.write(facet.format(k, 0, k + 1, 0, k, 1))
            k += 1
        out.write("endsolid strip\n")


def _ascii_stl_cut_at_the_end(path: Path, size: int) -> None:
    _ascii_stl(path, size)
    with path.open("a") as out:
        out.write("solid more\nfacet normal 0 0 1\n  outer loop\n    vertex 1 2")  # a corner cut off


def _off_polygon(path: Path, size: int) -> None:
    """One OFF polygon of every corner, over a circle of a thousand positions."""
    corners = size // 4
    circle = "".join(f"{np.cos(k * np.pi / 500):.6f} {np.sin(k * np.pi / 500):.6f} 0\n" for k in range(1000))
    with path.open("w") as out:
        out.write(f"OFF\n1000 1 0\n{circle}{corners}")
        out.writelines(f" {k % 1000}" for k in range(corners))
        out.write("\n")


def _blank_lines(path: Path, size: int) -> None:
    path.write_text("\n" * size)


def _one_long_line(path: Path, size: int) -> None:
    path.write_text(_TRIANGLE + "v" + " 1.5" * (size // 4) + "\n")


def _one_long_bad_number(path: Path, size: int) -> None:
    """Digits to the end, then a letter: a number's syntax that backtracks tries every split of them."""
    path.write_text(_TRIANGLE + "v 0 0 " + "1" * size + "x\n")


def _ply_of_blank_lines(path: Path, size: int) -> None:
    """An ASCII PLY whose rows are parted by blank lines: a reader of a numpy array per line holds one each."""
    header = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n")
    gap = "\n" * (size // 4)
    path.write_text(header + gap.join(["0 0 0", "1 0 0", "0 1 0", "3 0 1 2"]) + "\n")


def _scene_of_one_long_number(path: Path, size: int) -> None:
    """A number of every digit: tomllib's patterns for one hold over 100 bytes a digit."""
    size = min(size, SCENE_FILE_MEGABYTES * MEGABYTE)
    (path.parent / "tri.obj").write_text(_TRIANGLE)
    path.write_text('[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\nfov = ' + "1" * size + "\n")


def _scene_of_one_deep_key(path: Path, size: int) -> None:
    """One dotted key of every part: tomllib's cost for one grows with the square of its parts."""
    size = min(size, SCENE_FILE_MEGABYTES * MEGABYTE)
    (path.parent / "tri.obj").write_text(_TRIANGLE)
    path.write_text('[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\n\n' + "a" + ".a" * (size // 2) + " = 1\n")


def _scene_of_many_objects(path: Path, size: int) -> None:
    size = min(size, SCENE_FILE_MEGABYTES * MEGABYTE)
    (path.parent / "tri.obj").write_text(_TRIANGLE)
    entry = '[[objects]]\nmodel = "tri.obj"\nposition = [1, 2, 3]\n\n'
    path.write_text('[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\n\n' + entry * (size // len(entry)))


def _scene_of_many_materials(path: Path, size: int) -> None:
    size = min(size, SCENE_FILE_MEGABYTES * MEGABYTE)
    (path.parent / "tri.obj").write_text(_TRIANGLE)
    count = size // 90
    materials = "".join(f"[materials.m{k}]\nka = [0.1, 0.2, 0.3]\nkd = [0.4, 0.5, 0.6]\nks = [0.7, 0.8, 0.9]\n"
                        f"ns = 10\n\n" for k in range(count))
    path.write_text(materials + '[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\nmaterial = "m0"\n')


def _scene_of_many_nodes(path: Path, size: int) -> None:
    """A glTF whose nodes place one textured triangle again and again: every node is a placement."""
    size = min(size, SCENE_FILE_MEGABYTES * MEGABYTE)
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    uvs = np.array([[0, 0], [1, 0], [0, 1]], np.float32)
    blob = positions.tobytes() + uvs.tobytes() + np.array([0, 1, 2, 0], np.uint16).tobytes()
    picture = io.BytesIO()
    Image.new("RGB", (256, 256), (200, 60, 20)).save(picture, "PNG")
    node = '{"mesh":0,"translation":[%d,%d,0]}'
    count = size // (len(node % (1000, 1000)) + len("123456,"))  # a node and its entry in the scene's list
    views = [(0, 36), (36, 24), (60, 6)]
    document = {
        "asset": {"version": "2.0"}, "scene": 0,
        "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": offset, "byteLength": length} for offset, length in views],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0],
                       "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(picture.getvalue()).decode()}],
        "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "nodes": "NODES", "scenes": [{"nodes": "ROOTS"}],
    }
    text = json.dumps(document, separators=(",", ":"))
    nodes = ",".join(node % (2 * (k % 1000), 2 * (k // 1000)) for k in range(count))
    text = text.replace('"NODES"', f"[{nodes}]").replace('"ROOTS"', f"[{','.join(map(str, range(count)))}]")
    path.write_text(text)


def _ply_of_mixed_faces(encoding: str) -> Callable[[Path, int], None]:
    """A writer of a PLY of triangles and quads in turn over a circle of a thousand positions, as
    exporters write a model of both: rows of two lengths, each found only where the one before ends."""
    count = 996  # pairs of faces a block: the quads' last corner stays within the circle

    def write(path: Path, size: int) -> None:
        circle = np.stack([np.cos(np.arange(1000) * np.pi / 500), np.sin(np.arange(1000) * np.pi / 500),
                           np.zeros(1000)], axis=1)
        if encoding == "ascii":
            vertices = "".join(f"{x:.6f} {y:.6f} 0\n" for x, y, _ in circle).encode()
            block = "".join(f"3 {k} {k + 1} {k + 2}\n4 {k} {k + 1} {k + 2} {k + 3}\n" for k in range(count)).encode()
        else:
            vertices = circle.astype("<f4").tobytes()
            block = b"".join(struct.pack("<B3iB4i", 3, k, k + 1, k + 2, 4, k, k + 1, k + 2, k + 3)
                             for k in range(count))
        repeats = max(1, size // len(block))
        header = (f"ply\nformat {encoding} 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
                  f"property float z\nelement face {2 * count * repeats}\nproperty list uchar int vertex_indices\n"
                  "end_header\n")
        with path.open("wb") as out:
            out.write(header.encode() + vertices)
            out.writelines(block for _ in range(repeats))

    return write


def _off_coloured_faces(path: Path, size: int) -> None:
    """OFF triangles, each with a colour of fractions after its corners, as Geomview writes them."""
    circle = "".join(f"{np.cos(k * np.pi / 500):.6f} {np.sin(k * np.pi / 500):.6f} 0\n" for k in range(1000))
    block = "".join(f"3 {k} {k + 1} {k + 2} 0.{k % 10}5 0.5 0.75\n" for k in range(998))
    repeats = max(1, size // len(block))
    with path.open("w") as out:
        out.write(f"OFF\n1000 {998 * repeats} 0\n{circle}")
        out.writelines(block for _ in range(repeats))


SHAPES = (
    Shape("plain model (the baseline)", "plain.obj", _plain),
    Shape("the same, its last line cut", "cut.obj", _cut_at_the_end),
    Shape("one polygon of every corner", "polygon.obj", _one_polygon),
    Shape("a face without corners on every line", "no_corners.obj", _faces_without_corners),
    Shape("a usemtl before every face, two in turn", "materials.obj", _materials_in_turn(("red", "blue"))),
    # More than a piece of the compiled reader numbers (scan.NAMES_PER_PIECE): most are numbered one by one.
    Shape("a usemtl before every face, a thousand in turn", "many_materials.obj",
          _materials_in_turn([f"m{number}" for number in range(1000)])),
    Shape("blank lines only", "blank.obj", _blank_lines),
    Shape("one long v line", "long_line.obj", _one_long_line),
    Shape("one long number ending badly", "long_number.obj", _one_long_bad_number),
    Shape("ASCII PLY: its rows parted by blank lines", "blank.ply", _ply_of_blank_lines),
    Shape("ASCII PLY: triangles and quads in turn", "mixed_ascii.ply", _ply_of_mixed_faces("ascii")),
    Shape("binary PLY: triangles and quads in turn", "mixed.ply", _ply_of_mixed_faces("binary_little_endian")),
    Shape("OFF: one polygon of every corner", "polygon.off", _off_polygon),
    Shape("OFF: a colour after every face", "coloured.off", _off_coloured_faces),
    Shape("ASCII STL", "strip.stl", _ascii_stl),
    Shape("ASCII STL, its last line cut", "cut.stl", _ascii_stl_cut_at_the_end),
    Shape("scene file: many objects", "objects.toml", _scene_of_many_objects),
    Shape("scene file: one key of every part", "deep_key.toml", _scene_of_one_deep_key),
    Shape("scene file: one number of every digit", "long_number.toml", _scene_of_one_long_number),
    Shape("scene file: many materials", "materials.toml", _scene_of_many_materials),
    Shape("glTF: one textured triangle placed by many nodes", "nodes.gltf", _scene_of_many_nodes),
)


def shape_worker(argv: Sequence[str]) -> int:
    """The child: read one file as the viewer would, print seconds, peak memory and the outcome."""
    path = Path(argv[0])
    from marraztu.errors import ViewerError
    from marraztu.loaders.registry import load_model
    from marraztu.loaders.scenefile import load_scene

    read = load_scene if path.suffix == ".toml" else load_model
    baseline = peak_rss_bytes()
    start = time.perf_counter()
    try:
        read(path)
        outcome = "read"
    except ViewerError as error:
        outcome = "refused" + (f" at line {error.line}" if getattr(error, "line", None) else "")
    seconds = time.perf_counter() - start
    print(json.dumps({"seconds": seconds, "peak_rss_bytes": peak_rss_bytes() - baseline, "outcome": outcome}))
    return 0


_WORKER_CODE = ("import sys; from marraztu.devtools.bench.shapes import shape_worker; "
                "sys.exit(shape_worker(sys.argv[1:]))")


def _measure(path: Path) -> dict:
    done = subprocess.run([sys.executable, "-c", _WORKER_CODE, str(path)], capture_output=True, text=True)
    if done.returncode != 0:
        return {"seconds": None, "peak_rss_bytes": None, "outcome": "crashed: " + done.stderr.strip()[-80:]}
    return json.loads(done.stdout.strip().splitlines()[-1])


def shapes_section(config: BenchConfig, directory: Path) -> list[str]:
    rows = []
    plain: dict | None = None
    for shape in SHAPES:
        folder = directory / f"shape_{shape.file_name.split('.')[0]}"
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / shape.file_name
        progress(f"shapes: writing and reading {shape.label}")
        shape.write(path, config.shape_megabytes * MEGABYTE)
        result = _measure(path)
        plain = plain or result
        megabytes = path.stat().st_size / MEGABYTE
        seconds, rss = result["seconds"], result["peak_rss_bytes"]
        rows.append([shape.label, number(megabytes), result["outcome"], number(seconds),
                     number(seconds / megabytes if seconds is not None else None),
                     number(rss / MEGABYTE / megabytes if rss is not None else None),
                     ratio(seconds, plain["seconds"]), ratio(rss, plain["peak_rss_bytes"])])
    return [
        "## 5. Inputs shaped to break linear cost",
        "",
        f"Each file about {config.shape_megabytes} MB (scene files and the glTF at most {SCENE_FILE_MEGABYTES}), "
        "read once "
        "in a fresh process as the viewer reads it "
        "(a model through the reader registry, a scene file with its models); peak RSS is the process's "
        "peak minus its peak after imports. An error should cost about what a good file of the same "
        "size costs, and nothing should cost more than in proportion to its size.",
        "",
        *markdown_table(SHAPE_HEADERS, rows),
    ]
