"""marraztu as people install it: the wheel holds everything the program needs and nothing named
`app`; installed into a fresh virtual environment and run from another folder, it draws exactly what
the checkout draws; the sdist carries every file of the repository, tests included; and the import
layers hold (import-linter's contracts in pyproject.toml).

The fresh environment has its own interpreter and site-packages; the third-party packages it needs
(numpy, moderngl, ...) are lent to it from this one by a .pth line, so the test needs no network.
That line adds the folder to sys.path and nothing else: the checkout's editable install is a .pth
hook there, which Python does not run for a folder added this way.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.devtools.bench.inputs import SEED, grid_triangles, wavy_surface, write_obj
from marraztu.loaders.obj import COMPILED_READER_BYTES

ROOT = Path(__file__).resolve().parents[1]
KEYS = "0 1 F TAB ENTER*3 x*2"
SIZE = "160x120"


def tracked_files() -> list[str]:
    """The repository's files as git knows them, or every file of an unpacked sdist."""
    if (ROOT / ".git").exists() and shutil.which("git"):
        listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                                cwd=ROOT, capture_output=True, check=True).stdout
        return [name for name in listed.decode().split("\0") if name and (ROOT / name).is_file()]
    skipped = {".venv", "build", "dist", ".pytest_cache", "__pycache__", ".hypothesis"}
    return [str(path.relative_to(ROOT)) for path in ROOT.rglob("*")
            if path.is_file() and not skipped & set(path.relative_to(ROOT).parts)
            and not path.name.endswith((".pyc", ".egg-info"))]


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The wheel and the sdist, built by setuptools from a copy of the repository's files."""
    source = tmp_path_factory.mktemp("source")
    for name in tracked_files():
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, source / name)
    dist = tmp_path_factory.mktemp("dist")
    built = {}
    for kind in ("wheel", "sdist"):  # one process each: setuptools keeps state between builds
        build = f"import sys; from setuptools import build_meta; print('built', build_meta.build_{kind}(sys.argv[1]))"
        done = subprocess.run([sys.executable, "-c", build, str(dist)], cwd=source, capture_output=True,
                              text=True, timeout=300)
        assert done.returncode == 0, done.stderr[-3000:]
        built[kind] = dist / next(line.split()[1] for line in done.stdout.splitlines() if line.startswith("built "))
    return built


def test_the_wheel_holds_the_package_its_shaders_and_assets_and_no_app(built: dict[str, Path]) -> None:
    with zipfile.ZipFile(built["wheel"]) as wheel:
        names = set(wheel.namelist())
    top_level = {name.split("/")[0] for name in names}
    assert {name for name in top_level if not name.endswith(".dist-info")} == {"marraztu"}
    code = {"marraztu/" + str(path.relative_to(ROOT / "app")) for path in (ROOT / "app").rglob("*.py")}
    assert code <= names, sorted(code - names)
    data = {f"marraztu/{folder}/{path.name}" for folder in ("shaders", "assets")
            for path in (ROOT / folder).iterdir() if path.suffix in (".glsl", ".obj", ".ppm", ".toml")}
    assert data and data <= names, sorted(data - names)
    entry_points = next(name for name in names if name.endswith(".dist-info/entry_points.txt"))
    with zipfile.ZipFile(built["wheel"]) as wheel:
        assert "marraztu = marraztu.cli:main" in wheel.read(entry_points).decode()


def test_the_sdist_carries_every_file_of_the_repository(built: dict[str, Path]) -> None:
    with tarfile.open(built["sdist"]) as sdist:
        members = {name.split("/", 1)[1] for name in sdist.getnames() if "/" in name}
    missing = sorted(set(tracked_files()) - members)
    assert not missing, missing


@pytest.fixture(scope="module")
def installed(built: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A fresh virtual environment with the wheel installed; returns its bin folder."""
    venv = tmp_path_factory.mktemp("fresh") / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    python = venv / "bin" / "python"
    lent = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True).stdout.strip()
    (Path(lent) / "borrowed-dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    # Where the suite runs from an installed wheel, the lent folder holds marraztu too: pip would call it installed.
    done = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps",
                           "--no-index", "--ignore-installed", "--quiet", str(built["wheel"])],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return venv / "bin"


def run_installed(bin_folder: Path, *args: str, cwd: Path, **env_set: str) -> subprocess.CompletedProcess:
    env = {key: value for key, value in os.environ.items() if key not in ("PYTHONPATH", "VIRTUAL_ENV")} | env_set
    return subprocess.run([str(bin_folder / "marraztu"), *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def test_the_installed_program_draws_what_the_checkout_draws(installed: Path, tmp_path: Path) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    result = run_installed(installed, "screenshot", "-o", "shot.png", "--size", SIZE, "--keys", KEYS, cwd=elsewhere)
    assert result.returncode == 0, result.stderr
    checkout = subprocess.run([sys.executable, "-m", "marraztu", "screenshot", "-o", str(tmp_path / "checkout.png"),
                               "--size", SIZE, "--keys", KEYS], capture_output=True, text=True, timeout=300)
    assert checkout.returncode == 0, checkout.stderr
    from_wheel = np.asarray(Image.open(elsewhere / "shot.png"))
    from_checkout = np.asarray(Image.open(tmp_path / "checkout.png"))
    assert np.array_equal(from_wheel, from_checkout)
    assert (np.abs(from_wheel.astype(int) - [0, 0, 178]).sum(axis=2) > 30).mean() > 0.05, "almost blank"


def test_the_installed_program_reads_a_large_model_as_the_checkout_does(installed: Path, tmp_path: Path) -> None:
    """A file of megabytes goes through numba's compiled reader, compiled in the fresh environment, its
    machine code cached in the person's cache folder: numba's files in the package were left behind by
    `pip uninstall`, and the folder still imported as an empty package."""
    model = tmp_path / "grid.obj"
    write_obj(model, wavy_surface(cells=360, seed=SEED), grid_triangles(360), uv_and_normals=False)
    assert model.stat().st_size > COMPILED_READER_BYTES
    args = ["--empty", "--size", SIZE, "--keys", "0 1", str(model)]
    cache = tmp_path / "cache"
    installed_run = run_installed(installed, "screenshot", "-o", str(tmp_path / "wheel.png"), *args, cwd=tmp_path,
                                  XDG_CACHE_HOME=str(cache))
    assert installed_run.returncode == 0, installed_run.stderr
    package = next(installed.parent.glob("lib/python*/site-packages/marraztu"))
    assert not [path for path in package.rglob("*") if path.suffix in (".nbi", ".nbc")]
    if "NUMBA_CACHE_DIR" not in os.environ:
        assert list((cache / "marraztu" / "numba").rglob("*.nbi"))
    checkout = subprocess.run([sys.executable, "-m", "marraztu", "screenshot", "-o", str(tmp_path / "checkout.png"),
                               *args], capture_output=True, text=True, timeout=300)
    assert checkout.returncode == 0, checkout.stderr
    from_wheel = np.asarray(Image.open(tmp_path / "wheel.png"))
    assert np.array_equal(from_wheel, np.asarray(Image.open(tmp_path / "checkout.png")))
    assert len(np.unique(from_wheel.reshape(-1, from_wheel.shape[-1]), axis=0)) > 20, "not a lit surface"


def test_the_installed_package_is_the_wheels_and_there_is_no_app(installed: Path, tmp_path: Path) -> None:
    (tmp_path / "app").mkdir()  # a person's own folder called app must not matter
    (tmp_path / "app" / "__init__.py").write_text("raise SystemExit('the wrong app')\n")
    probe = ("import importlib.util, marraztu, marraztu.resources as r; "
             "print(marraztu.__file__); print(r.SHADER_DIR); print(importlib.util.find_spec('app') is None)")
    env = {key: value for key, value in os.environ.items() if key != "PYTHONPATH"}
    shown = subprocess.run([str(installed / "python"), "-I", "-c", probe], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=120)
    assert shown.returncode == 0, shown.stderr
    package, shaders, no_app = shown.stdout.split()
    prefix = str(installed.parent)
    assert package.startswith(prefix) and shaders.startswith(prefix), (package, shaders)
    assert no_app == "True"
    version = run_installed(installed, "--version", cwd=tmp_path)
    assert version.returncode == 0 and version.stdout.strip().startswith("marraztu ")


def test_the_import_layers_hold() -> None:
    """import-linter's contracts (pyproject.toml): no upward import, no cycle at any depth."""
    lint = Path(sys.executable).with_name("lint-imports")
    done = subprocess.run([str(lint)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-4000:]
    assert "0 broken" in done.stdout


def test_ci_installs_what_make_test_runs_on_a_fresh_debian_or_ubuntu() -> None:
    """.ci/run runs `make test`, whose first step is `python3 -m venv`: neither `make` nor the venv module
    (python3-venv) comes with a fresh Debian or Ubuntu, so it installs them with the GL and X packages."""
    ci = (ROOT / ".ci" / "run").read_text()
    packages = set(re.search(r"for pkg in ([^;]+);", ci).group(1).split())
    assert "make test" in ci and "python3 -m venv" in (ROOT / "Makefile").read_text()
    assert {"make", "python3-venv"} <= packages, sorted(packages)
