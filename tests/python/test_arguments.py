"""The module as a Python user calls it ("Python speaks Python"): NumPy values taken as
numbers, every argument checked with an error naming it, the CLI's ranges on the keywords,
keywords (not CLI flags) in messages, independent copies, NUL bytes refused, the VTU's cell
fields on Result, a clean namespace, and `pip install .` into a virtual environment.

Run by ctest (hemicontact.python) with PYTHONPATH=<build>/python and HEMICONTACT_SOURCE_DIR.
"""
import copy
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hemicontact as hc

SOURCE = Path(os.environ.get("HEMICONTACT_SOURCE_DIR", Path(__file__).resolve().parents[2]))
FIG2 = SOURCE / "problems" / "sofonea2017-fig2.json"
SOFTENING = SOURCE / "problems" / "minima-softening.json"


@pytest.fixture(scope="module")
def fig2_4():
    return hc.solve(hc.Scene.load(FIG2, "mesh.n=4"))


def test_numpy_values_are_numbers():
    scene = hc.Scene.load(FIG2)
    scene["mesh.n"] = np.int64(8)
    assert scene["mesh.n"] == 8 and scene.overrides == ["mesh.n=8"]
    scene["material.E"] = np.float32(2500.0)
    assert scene["material.E"] == 2500.0
    scene["mesh.x"] = np.array([0.0, 2.0])
    assert scene["mesh.x"] == [0.0, 2.0]
    scene["contact.friction.mu"] = np.float64(0.3)
    # A sweep over np.arange, as a Python user writes it.
    for n in np.arange(4, 7):
        scene["mesh.n"] = n
    assert scene["mesh.n"] == 6
    # In a dict, and in solve's options.
    d = json.loads(FIG2.read_text())
    d["mesh"]["n"] = np.int32(4)
    d["mesh"]["x"] = (np.float64(0), np.float64(1))
    assert hc.Scene(d)["mesh.n"] == 4
    assert hc.solve(hc.Scene.load(FIG2, "mesh.n=4"), tol=np.float64(1e-10)).ok


def test_values_json_cannot_hold_are_refused_naming_the_key():
    scene = hc.Scene.load(FIG2)
    with pytest.raises(hc.SceneError, match=r"scene key 'material.E': number is not finite \(nan\)"):
        scene["material.E"] = np.float64("nan")
    with pytest.raises(TypeError, match="scene key 'material.E'.*complex"):
        scene["material.E"] = 1 + 2j
    with pytest.raises(TypeError, match="key: expected a dotted scene key"):
        scene[3] = 4
    assert scene.overrides == []


def test_arguments_of_the_wrong_kind_are_type_errors_naming_them():
    with pytest.raises(TypeError, match="scene: expected a Scene, a dict in the scene format or a scene file's path, got int"):
        hc.solve(42)
    with pytest.raises(TypeError, match="starts: expected an integer from 0 to 10000, got '3'"):
        hc.minima(SOFTENING, starts="3")
    with pytest.raises(TypeError, match="backend: expected a backend name"):
        hc.solve(FIG2, backend=3)
    with pytest.raises(TypeError, match=r"levels\[0\]: expected an integer"):
        hc.converge(FIG2, levels=[4.7], reference=16)  # refused, not truncated to 4
    with pytest.raises(TypeError, match="reference: expected an integer"):
        hc.converge(FIG2, levels=[4], reference=16.0)
    with pytest.raises(TypeError, match="force: expected True or False"):
        hc.solve(hc.Scene.load(FIG2, "mesh.n=2")).write("/nonexistent/x", force="yes")
    with pytest.raises(TypeError, match="user_starts: expected an iterable"):
        hc.minima(SOFTENING, user_starts=3)
    with pytest.raises(TypeError, match=r"backends\[1\]: expected a backend name"):
        hc.minima(SOFTENING, backends=["ipopt", 2])


def test_the_clis_ranges_hold_on_the_keywords():
    for kwargs, message in [
        (dict(load_path_steps=10**9), "load_path_steps: expected an integer from 0 to 10000"),
        (dict(starts=-1), "starts: expected an integer from 0 to 10000, got '-1'"),
        (dict(seed=2**32), "seed: expected an integer from 0 to 4294967295"),
        (dict(box=math.inf), "box: expected a positive number, got 'inf'"),
        (dict(box=0), "box: expected a positive number"),
        (dict(group_tol=float("nan")), "group_tol: expected a positive number"),
        (dict(user_starts=[[0.0, math.nan]]), r"user_starts\[0\]: start values must be finite numbers"),
        (dict(backends=""), "backends: expected at least one backend name"),
    ]:
        with pytest.raises(ValueError, match=message):
            hc.minima(SOFTENING, **kwargs)
    with pytest.raises(ValueError, match="target_error: expected a positive number"):
        hc.adapt(FIG2, target_error=-0.1)


def test_a_str_of_backends_is_names_not_letters():
    # "ipopt" once ran the backends 'i', 'p', 'o', ...: one name (a comma-separated list as the CLI's).
    with pytest.raises(hc.SceneError) as e:
        hc.minima(SOFTENING, starts=0, load_path_steps=0, backends="nosuchbackend")
    assert "'n'" not in str(e.value) and "nosuchbackend" in str(e.value)
    r = hc.minima(SOFTENING, starts=0, load_path_steps=0, backends="newton")
    assert {run["backend"] for run in r.report["runs"]} == {"newton"}


def test_messages_name_keywords_not_flags(fig2_4, tmp_path):
    fig2_4.write(tmp_path / "o")
    with pytest.raises(hc.SceneError) as e:
        fig2_4.write(tmp_path / "o")
    assert "force=True" in str(e.value) and "--force" not in str(e.value), str(e.value)
    assert "--out" not in str(e.value)
    with pytest.raises(ValueError) as e:
        hc.converge(FIG2, levels="4,abc")
    assert "--levels" not in str(e.value) and "levels" in str(e.value)


def test_copies_are_independent():
    scene = hc.Scene.load(FIG2)
    for c in (copy.copy(scene), copy.deepcopy(scene), scene.copy(), hc.Scene(scene)):
        assert c is not scene and c._s is not scene._s
        c["mesh.n"] = 8
        assert scene["mesh.n"] == 64 and scene.overrides == []


def test_a_scene_file_by_name():
    scene = hc.Scene(FIG2)
    assert scene.path == str(FIG2) and scene["mesh.n"] == 64
    assert hc.Scene(str(FIG2))["material.E"] == 2000
    with pytest.raises(hc.SceneError, match="not found"):
        hc.Scene(str(FIG2) + ".missing")
    with pytest.raises(ValueError, match="directory: a scene file's relative paths"):
        hc.Scene(FIG2, directory="/tmp")
    with pytest.raises(TypeError, match="scene: expected a dict"):
        hc.Scene(3.5)


def test_paths_with_a_nul_byte_are_refused(fig2_4, tmp_path):
    with pytest.raises(ValueError, match="folder: the path .* holds a NUL byte"):
        fig2_4.write(str(tmp_path / "a\0b"))
    assert not (tmp_path / "a").exists()
    with pytest.raises(ValueError, match="NUL byte"):
        hc.Scene.load(str(FIG2) + "\0x")
    with pytest.raises(ValueError, match="NUL byte"):
        hc.solve(str(FIG2) + "\0x")
    # A scene's mesh.file with one: the scene checker's refusal, naming the key.
    with pytest.raises(hc.SceneError, match="scene key 'mesh.file': the file name holds a NUL byte"):
        hc.Scene.load(FIG2)["mesh.file"] = "m.msh\0.txt"


def test_stress_and_strain_are_the_vtus(fig2_4, tmp_path):
    meshio = pytest.importorskip("meshio")
    r = fig2_4
    cells = r.cells.shape[0]
    assert r.strain.shape == (cells, 3) and r.stress.shape == (cells, 3) and r.von_mises.shape == (cells,)
    r.write(tmp_path / "vtu")
    m = meshio.read(tmp_path / "vtu" / "solution.vtu")
    np.testing.assert_allclose(m.cell_data["strain"][0], r.strain, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(m.cell_data["stress"][0], r.stress, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(m.cell_data["von_mises"][0].ravel(), r.von_mises, rtol=1e-12, atol=1e-300)
    assert np.abs(r.stress).max() > 0  # a loaded body: the check above compares something
    a = r.stress
    a[:] = 0
    assert np.abs(r.stress).max() > 0  # each access a copy


def test_the_namespace_is_the_api():
    public = {n for n in dir(hc) if not n.startswith("_")}
    assert public == set(hc.__all__) - {"__version__"}, public ^ set(hc.__all__)
    for leaked in ("os", "namedtuple", "annotations", "TYPE_CHECKING"):
        assert not hasattr(hc, leaked), leaked


def test_export_to_xdmf(fig2_4, tmp_path):
    # docs/python.md's export example: meshio's XDMF writer needs h5py (scripts/install-deps.sh).
    pytest.importorskip("meshio")
    pytest.importorskip("h5py")
    fig2_4.export(tmp_path / "u.xdmf")
    assert (tmp_path / "u.xdmf").stat().st_size > 0


@pytest.mark.skipif(not os.environ.get("HEMICONTACT_BUILD_DIR"), reason="needs HEMICONTACT_BUILD_DIR (set by ctest)")
def test_pip_install_into_a_venv(tmp_path):
    """`pip install .` offline into a fresh virtual environment, with Debian's pip, setuptools and
    wheel: the installed module imports (not the build tree's) and solves."""
    venv = tmp_path / "v"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    p = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", "--no-index", "."],
                       cwd=SOURCE, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    code = ("import hemicontact as hc, sys; r = hc.solve(hc.Scene.load(sys.argv[1], 'mesh.n=4')); "
            "print(hc.__file__, r.ok, hc.__version__)")
    p = subprocess.run([str(venv / "bin" / "python"), "-c", code, str(FIG2)], cwd=tmp_path, env=env,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    where, ok, version = p.stdout.split()
    assert where.startswith(str(venv)) and ok == "True" and version == hc.__version__, p.stdout
