"""hemicontact from Python: static frictional contact of an elastic body with a soft-layer foundation.

The same solver as the ``hemicontact`` program, on the same scene files::

    import hemicontact as hc
    scene = hc.Scene.load("problems/sofonea2017-fig2.json")
    scene["mesh.n"] = 64                     # as --set mesh.n=64, checked against the schema
    r = hc.solve(scene)                      # as `hemicontact solve` (no files written)
    r.energy, r.certificate.passed, r.status_counts
    r.points, r.cells, r.u, r.gamma3["sigma_nu"], r.lam   # NumPy arrays (copies)
    r.report                                 # the dict of report.json
    r.write("out/fig2")                      # report.json, solution.vtu, gamma3.csv

Errors in a scene (an unknown key, a value out of range) raise :class:`SceneError`, a
``ValueError`` whose message is the CLI's. A solve releases the GIL (solves in threads run side
by side) and stops at Ctrl-C with ``KeyboardInterrupt``. Progress lines go to
``logging.getLogger("hemicontact")`` (INFO; ``logging.basicConfig(level=logging.INFO)`` shows them).
"""
from __future__ import annotations

# Private names only (the namespace is the API: dir(hemicontact) shows __all__ and nothing of the
# implementation's imports).
import math as _math
import numbers as _numbers
import os as _os
from collections import namedtuple as _namedtuple
from collections.abc import Mapping as _Mapping

# The annotations are not evaluated (postponed, PEP 563) and the type checkers read __init__.pyi:
# typing is imported for them only, which keeps it (~5 ms) out of a script's start.
_TYPE_CHECKING = False
if _TYPE_CHECKING:
    from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

from . import _hemicontact as _core
from ._hemicontact import HemicontactError, SceneError, __version__

del annotations  # the __future__ import's name: not part of the API

__all__ = [
    "Scene", "Result", "Certificate", "MinimaResult", "PathResult", "SceneError", "HemicontactError",
    "solve", "adapt", "minima", "path", "converge", "backends", "random_scene", "__version__",
]


# ------------------------------------------------------------------ argument checks
# Every public function checks its arguments here, naming the keyword: a TypeError for a value of
# the wrong kind, a ValueError (SceneError) for one out of the CLI's range.

def _type_name(value: Any) -> str:
    return type(value).__name__


def _is_numpy(value: Any) -> bool:
    # Without importing NumPy (a script that never uses it does not pay for it).
    return type(value).__module__ == "numpy" and callable(getattr(value, "tolist", None))


def _plain(value: Any, name: str) -> Any:
    """``value`` as JSON-able plain Python (for the scene's JSON): NumPy scalars and arrays become
    numbers and lists, tuples lists; ``name`` (the scene key) is what a refusal names."""
    if _is_numpy(value):
        value = value.tolist()  # a NumPy scalar gives a Python number, an array nested lists
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, _numbers.Integral):
        return int(value)
    if isinstance(value, _numbers.Real):
        x = float(value)
        if not _math.isfinite(x):
            # The scene checker's own words (scene numbers must be finite; JSON has no inf).
            raise SceneError(f"scene key '{name}': number is not finite ({x!r})")
        return x
    if isinstance(value, _Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise TypeError(f"scene key '{name}': the keys of a scene object are strings, got {k!r} "
                                f"({_type_name(k)})")
            out[k] = _plain(v, f"{name}.{k}" if name else k)
        return out
    if isinstance(value, (list, tuple)):
        return [_plain(v, f"{name}[{i}]") for i, v in enumerate(value)]
    raise TypeError(f"scene key '{name}': expected a number, string, bool, None, list or dict (as JSON "
                    f"holds), got {_type_name(value)}")


def _path(value: Any, name: str) -> str:
    """A file or folder name given as ``name``: a str or os.PathLike, without NUL bytes."""
    if not isinstance(value, (str, _os.PathLike)):
        raise TypeError(f"{name}: expected a path (str or os.PathLike), got {_type_name(value)}")
    p = _os.fspath(value)
    if not isinstance(p, str):
        raise TypeError(f"{name}: expected a str path, got {_type_name(p)}")
    if "\0" in p:
        # The system calls end a name at its first NUL byte: "dir/a\0b" would be dir/a.
        raise ValueError(f"{name}: the path {p!r} holds a NUL byte")
    if not p:
        raise ValueError(f"{name}: empty path")
    return p


def _integer(value: Any, name: str, lo: int, hi: int) -> int:
    """An integer in [lo, hi] (the CLI's range and words); floats are refused, not truncated."""
    if _is_numpy(value) and getattr(value, "ndim", 1) == 0:
        value = value.tolist()
    if isinstance(value, bool) or not isinstance(value, _numbers.Integral):
        raise TypeError(f"{name}: expected an integer from {lo} to {hi}, got {value!r} ({_type_name(value)})")
    if not lo <= int(value) <= hi:
        raise ValueError(f"{name}: expected an integer from {lo} to {hi}, got '{int(value)}'")
    return int(value)


def _flag(value: Any, name: str) -> bool:
    """A bool (NumPy's too); 0, 1 and "yes" are refused rather than read."""
    if _is_numpy(value) and getattr(value, "ndim", 1) == 0:
        value = value.tolist()
    if not isinstance(value, bool):
        raise TypeError(f"{name}: expected True or False, got {value!r} ({_type_name(value)})")
    return value


def _positive(value: Any, name: str) -> float:
    """A positive finite number (the CLI's --group-tol, --box, an error target)."""
    if _is_numpy(value) and getattr(value, "ndim", 1) == 0:
        value = value.tolist()
    if isinstance(value, bool) or not isinstance(value, _numbers.Real):
        raise TypeError(f"{name}: expected a positive number, got {value!r} ({_type_name(value)})")
    x = float(value)
    if not (x > 0 and _math.isfinite(x)):
        raise ValueError(f"{name}: expected a positive number, got '{x!r}'")
    return x


def _names(value: Any, name: str) -> List[str]:
    """Names given as one str ("ipopt", or "ipopt,newton" as the CLI's list) or a sequence of str."""
    if isinstance(value, str):
        items = [b.strip() for b in value.split(",") if b.strip()]
    elif isinstance(value, (list, tuple)):
        items = list(value)
        for i, b in enumerate(items):
            if not isinstance(b, str):
                raise TypeError(f"{name}[{i}]: expected a backend name (str), got {b!r} ({_type_name(b)})")
    else:
        raise TypeError(f"{name}: expected a backend name, a comma-separated str or a list of names, "
                        f"got {_type_name(value)}")
    if not items:
        raise ValueError(f"{name}: expected at least one backend name, got {value!r}")
    return items


def _bool(value: Any, name: str) -> bool:
    if _is_numpy(value) and getattr(value, "ndim", 1) == 0:
        value = value.tolist()
    if not isinstance(value, bool):
        raise TypeError(f"{name}: expected True or False, got {value!r} ({_type_name(value)})")
    return value


# The library's messages name the CLI's options; from Python they name the keywords instead.
_FLAG_KEYWORDS = {
    "force": "force=True", "out": "folder", "starts": "starts", "start": "user_starts", "seed": "seed",
    "backends": "backends", "backend": "backend", "group-tol": "group_tol", "box": "box",
    "load-path-steps": "load_path_steps", "levels": "levels", "reference": "reference",
}


class _Keywords:
    """Re-raise the library's errors with keywords where they name the CLI's options."""

    def __enter__(self) -> None:
        return None

    def __exit__(self, kind: Any, error: Any, tb: Any) -> bool:
        if isinstance(error, (SceneError, HemicontactError)):
            import re  # on an error only: re stays out of a script's start

            flags = "|".join(sorted(map(re.escape, _FLAG_KEYWORDS), key=len, reverse=True))
            text = re.sub(r"--(" + flags + r")\b", lambda m: _FLAG_KEYWORDS[m.group(1)], str(error))
            if text != str(error):
                raise type(error)(text) from None
        return False


class Scene:
    """A scene: a scene file (or a dict in the same format) and the ``--set`` changes made to it.

    ``scene["mesh.n"] = 128`` is ``--set mesh.n=128``: the whole scene is validated again with the
    CLI's checks, and a bad key or value raises :class:`SceneError` leaving the scene unchanged.
    ``scene["mesh.nx"]`` reads a value of the effective scene (every default filled in).
    """

    def __init__(self, scene: Union[Mapping[str, Any], "Scene", str, _os.PathLike],
                 directory: Optional[Union[str, _os.PathLike]] = None):
        """Validate a scene given as a dict (the JSON of a scene file), or read a scene file.

        ``directory`` is where relative paths in a dict (``mesh.file``) are taken from (default:
        the current folder); a scene file's are taken from its own folder. A :class:`Scene` is
        copied. NumPy numbers and arrays in a dict are taken as the numbers and lists they hold.
        """
        if isinstance(scene, (str, _os.PathLike)):
            if directory is not None:
                raise ValueError("directory: a scene file's relative paths are taken from its own folder; "
                                 "directory is for a scene given as a dict")
            self._s = _core._Scene.load(_path(scene, "scene"))
        elif isinstance(scene, Scene):
            self._s = scene._s.copy()
        elif isinstance(scene, _Mapping):
            where = _path(directory, "directory") if directory is not None else "."
            self._s = _core._Scene.from_dict(_plain(scene, ""), where)
        else:
            raise TypeError(f"scene: expected a dict in the scene format, a Scene or a scene file's path, "
                            f"got {_type_name(scene)}")

    @classmethod
    def load(cls, path: Union[str, _os.PathLike], *assignments: str) -> "Scene":
        """Read a scene file, applying ``--set``-style ``"key=value"`` assignments in order."""
        self = cls.__new__(cls)
        self._s = _core._Scene.load(_path(path, "path"))
        if assignments:
            self._s.apply(_assignment_list(assignments))
        return self

    def __getitem__(self, key: str) -> Any:
        """The value at a dotted key of the effective scene (``KeyError`` when absent)."""
        if not isinstance(key, str):
            raise TypeError(f"key: expected a dotted scene key (str), got {_type_name(key)}")
        return self._s.get(key)

    def __setitem__(self, key: str, value: Any) -> None:
        """``--set key=value`` with the value as JSON; raises :class:`SceneError` if invalid.
        NumPy numbers and arrays are taken as the numbers and lists they hold."""
        if not isinstance(key, str):
            raise TypeError(f"key: expected a dotted scene key (str), got {_type_name(key)}")
        self._s.set(key, _plain(value, key))

    def set(self, *assignments: str) -> "Scene":
        """Apply ``--set`` assignments as the CLI takes them (``"mesh.type=gmsh"``); returns self."""
        self._s.apply(_assignment_list(assignments))
        return self

    def copy(self) -> "Scene":
        """An independent copy (changes to it leave this scene as it is)."""
        return Scene(self)

    def __copy__(self) -> "Scene":
        return Scene(self)

    def __deepcopy__(self, memo: Any) -> "Scene":
        return Scene(self)

    def to_dict(self) -> Dict[str, Any]:
        """The effective scene: the file with the changes applied and every default filled in."""
        return self._s.effective()

    @property
    def path(self) -> Optional[str]:
        """The scene file (None for a scene made from a dict)."""
        return self._s.path

    @property
    def directory(self) -> str:
        """The folder relative paths in the scene are taken from."""
        return self._s.directory

    @property
    def overrides(self) -> List[str]:
        """The ``--set`` assignments applied so far, in order."""
        return list(self._s.overrides)

    def __repr__(self) -> str:
        where = repr(self.path) if self.path else "<dict>"
        return f"Scene({where}, overrides={self.overrides!r})"


def _assignment_list(assignments: Any) -> List[str]:
    for i, a in enumerate(assignments):
        if not isinstance(a, str):
            raise TypeError(f"assignments[{i}]: expected a \"key=value\" str, got {_type_name(a)}")
    return list(assignments)


class Certificate(_namedtuple("Certificate", "passed max_residual tol residuals")):
    """The a-posteriori certificate of a solution (docs/model.md §4): it passes when every normalized
    residual (``residuals``, by name) is at most ``tol`` (check.certificate_tol).

    Fields: passed (bool), max_residual (float), tol (float), residuals (dict name -> float).
    (A named tuple rather than a dataclass: importing dataclasses costs ~25 ms of every import.)
    """

    __slots__ = ()


class Result:
    """One solve's answer. Arrays are NumPy copies: they stay valid when the Result is gone."""

    def __init__(self, solved: Any):
        self._r = solved
        self._report: Optional[Dict[str, Any]] = None
        self._cells: Optional[Dict[str, Any]] = None

    @property
    def energy(self) -> float:
        """Π(u), the unsmoothed energy (report.json "energy")."""
        return self._r.energy

    @property
    def energy_norm(self) -> float:
        """sqrt(a(u, u))."""
        return self._r.energy_norm

    @property
    def ok(self) -> bool:
        """Converged and certified (report.json "ok"; the CLI exits 0)."""
        return self._r.ok

    @property
    def message(self) -> str:
        """The verdict in words."""
        return self._r.message

    @property
    def solved_by(self) -> str:
        """What produced the answer, e.g. "exact" or "ipopt+exact"."""
        return self._r.solved_by

    @property
    def certificate(self) -> Certificate:
        """passed, max_residual, tol and each residual by name."""
        c = self._r.certificate
        return Certificate(c["passed"], c["max_residual"], c["tol"], dict(c["residuals"]))

    @property
    def statuses(self) -> List[str]:
        """Each Γ3 node's status, e.g. "contact/stick", in Γ3 order."""
        return self._r.statuses

    @property
    def status_counts(self) -> Dict[str, int]:
        """How many Γ3 nodes have each status part (separated, compliance, contact, stick, slip+, ...)."""
        return self._r.status_counts

    @property
    def points(self):
        """Node coordinates, shape (nodes, d)."""
        return self._r.points

    @property
    def cells(self):
        """Cells as node indices, shape (cells, d + 1), int64."""
        return self._r.cells

    @property
    def u(self):
        """The displacement per node, shape (nodes, d)."""
        return self._r.u

    @property
    def gamma3(self) -> Dict[str, Any]:
        """The Γ3 nodes, arrays in Γ3 order: node (index), x (coordinates), normal, w (weights),
        g, u_nu, u_tau, sigma_nu, sigma_tau (the reactions), xi, lambda (F_b(u_ν))."""
        return self._r.gamma3

    def _cell_fields(self) -> Dict[str, Any]:
        if self._cells is None:
            self._cells = self._r.cell_fields
        return self._cells

    @property
    def strain(self):
        """The strain per cell (constant on P1 elements), Voigt: ε11, ε22, 2ε12 in 2D; ε11, ε22,
        ε33, 2ε23, 2ε13, 2ε12 in 3D; shape (cells, 3 or 6): the VTU's "strain"."""
        return self._cell_fields()["strain"].copy()

    @property
    def stress(self):
        """The stress per cell (the material's, of the strain), Voigt as ``strain``: the VTU's "stress"."""
        return self._cell_fields()["stress"].copy()

    @property
    def von_mises(self):
        """The von Mises stress per cell: the VTU's "von_mises"."""
        return self._cell_fields()["von_mises"].copy()

    @property
    def lam(self):
        """λ = F_b(u_ν) per Γ3 node (the friction bound)."""
        return self._r.gamma3["lambda"]

    @property
    def report(self) -> Dict[str, Any]:
        """The report.json dict the CLI writes for this solve (without "files")."""
        if self._report is None:
            self._report = self._r.report()
        return self._report

    @property
    def summary(self) -> str:
        """The summary `hemicontact solve` prints."""
        return self._r.summary()

    @property
    def timings(self) -> Dict[str, float]:
        """Seconds per phase of the solve."""
        return self._r.timings

    def write(self, folder: Union[str, _os.PathLike], force: bool = False) -> None:
        """Write what `hemicontact solve --out folder` writes: report.json, solution.vtu and
        gamma3.csv (as the scene's output block says; adapt_levels.json for an adaptive solve).
        The folder's rules are the CLI's: results of an earlier run are replaced only with force."""
        where = _path(folder, "folder")
        with _Keywords():
            self._r.write(where, _bool(force, "force"))

    def to_meshio(self):
        """The mesh with u as point data, as a meshio.Mesh (needs python3-meshio)."""
        try:
            import meshio
        except ImportError as e:  # pragma: no cover - depends on the machine
            raise ImportError("Result.to_meshio needs meshio (Debian: apt-get install python3-meshio)") from e
        points = self.points
        cells = self.cells
        kind = "triangle" if cells.shape[1] == 3 else "tetra"
        return meshio.Mesh(points, [(kind, cells)], point_data={"u": self.u})

    def export(self, path: Union[str, _os.PathLike], **kwargs: Any) -> None:
        """Write the mesh and u with meshio in the format its extension names (.vtu, .xdmf, .msh, ...)."""
        self.to_meshio().write(_path(path, "path"), **kwargs)

    def __repr__(self) -> str:
        return f"Result(energy={self.energy!r}, ok={self.ok}, solved_by={self.solved_by!r})"


def _scene(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike]) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, _os.PathLike, _Mapping)):
        return Scene(scene)
    raise TypeError(f"scene: expected a Scene, a dict in the scene format or a scene file's path, "
                    f"got {_type_name(scene)}")


def _assignments(backend: Optional[str], options: Mapping[str, Any]) -> List[str]:
    # solve(scene, tol=1e-12, fixed_point__tol_u=1e-9): solver.tol, solver.fixed_point.tol_u.
    import json

    out = []
    if backend is not None:
        if not isinstance(backend, str):
            raise TypeError(f"backend: expected a backend name (str) or None, got {_type_name(backend)}")
        out.append("solver.backend=" + json.dumps(backend))
    for key, value in options.items():
        dotted = "solver." + key.replace("__", ".")
        out.append(dotted + "=" + json.dumps(_plain(value, dotted)))
    return out


def solve(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike], backend: Optional[str] = None,
          **options: Any) -> Result:
    """Solve a scene as `hemicontact solve` does (adaptively when adapt.target_error is set).

    ``backend`` is ``--backend``; each keyword is a ``solver.`` key, ``__`` for a dot:
    ``solve(scene, tol=1e-12, fixed_point__tol_u=1e-9)``. The scene itself is not changed.
    Raises :class:`SceneError` for bad input; a solve that does not converge or certify returns
    a Result with ``ok`` False (as the CLI's exit codes 3 and 4).
    """
    s = _scene(scene)
    return Result(_core.solve(s._s, _assignments(backend, options)))


def adapt(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike], target_error: float = 0.01,
          backend: Optional[str] = None, **options: Any) -> Result:
    """The adaptive solve (`hemicontact solve` with adapt.target_error): refine until the relative
    error estimate is at most ``target_error``; the Result is the final mesh's, its report holds
    the levels under "adapt"."""
    import json

    s = _scene(scene)
    target = _positive(target_error, "target_error")
    extra = _assignments(backend, options) + ["adapt.target_error=" + json.dumps(target)]
    return Result(_core.solve(s._s, extra))


class MinimaResult:
    """`hemicontact minima`'s answer: ``report`` is the dict of minima.json, ``solutions`` a
    :class:`Result` per distinct solution, lowest energy first (as solution_<k>.vtu);
    ``unseen`` the Chao1 estimate of the solutions the random starts missed, ``barriers`` (with
    ``barriers=True``) the pairs of minima.json's "barriers", each side's saddle verified or not."""

    def __init__(self, report: Dict[str, Any], solutions: List[Result]):
        self.report = report
        self.solutions = solutions
        self.unseen = report.get("unseen", {})
        self.barriers = report.get("barriers", [])

    def __repr__(self) -> str:
        return f"MinimaResult({len(self.solutions)} distinct solutions, {len(self.report.get('runs', []))} runs)"


class PathResult:
    """`hemicontact path`'s answer: ``report`` is the dict of path.json, ``states`` a
    :class:`Result` per recorded state (as state_<k>.vtu), ``jumps`` its jumps; the per-state
    columns of path.csv as NumPy arrays: ``load``, ``energy``, ``reaction``, ``mean_u_nu``,
    ``max_u_nu`` and ``certified``."""

    def __init__(self, report: Dict[str, Any], states: List[Result]):
        import numpy as np

        self.report = report
        self.states = states
        self.jumps = report["jumps"]
        rows = report["states"]
        for key in ("load", "energy", "reaction", "mean_u_nu", "max_u_nu"):
            setattr(self, key, np.array([np.nan if r[key] is None else r[key] for r in rows], dtype=float))
        self.certified = np.array([r["certified"] for r in rows], dtype=bool)

    def __repr__(self) -> str:
        return (f"PathResult({len(self.states)} states, {len(self.jumps)} jumps, "
                f"{'complete' if self.report['complete'] else 'stopped: ' + self.report['failure']})")


def _loads(value: Any) -> List[float]:
    """Load factors: the CLI's "0,2,0" or a sequence of finite numbers (NumPy arrays too)."""
    import numpy as np

    if isinstance(value, str):
        parts = [p.strip() for p in value.split(",")]
        try:
            value = [float(p) for p in parts]
        except ValueError:
            raise ValueError(f"load: expected numbers separated by commas, got {value!r}") from None
    if isinstance(value, (bytes, _Mapping)) or not hasattr(value, "__iter__"):
        raise TypeError(f"load: expected a sequence of load factors, got {_type_name(value)}")
    try:
        a = np.asarray(list(value), dtype=float).ravel()
    except (TypeError, ValueError) as e:
        raise TypeError(f"load: expected a sequence of numbers ({e})") from None
    if a.size < 2:
        raise ValueError("load: needs at least two load factors (e.g. [0, 2, 0])")
    if not np.all(np.isfinite(a)):
        raise ValueError("load: load factors must be finite numbers")
    return [float(x) for x in a]


def path(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike], load: Any = (0, 1), steps: int = 20,
         bisection_tol: float = 1e-6) -> PathResult:
    """A quasi-static load history, as `hemicontact path` (--load, --steps, --bisection-tol):
    the loads scaled by factors through the corners of ``load``, each step started from the last
    certified state, every jump located by bisection to ``bisection_tol``."""
    s = _scene(scene)
    corners = _loads(load)
    n_steps = _integer(steps, "steps", 1, _core.limits["path_steps"])
    tol = _positive(bisection_tol, "bisection_tol")
    with _Keywords():
        out = _core.path(s._s, [], corners, n_steps, tol)
    return PathResult(out["report"], [Result(r) for r in out["states"]])


def _starts(user_starts: Any) -> List[Any]:
    """The user's start vectors as finite float arrays, each refusal naming user_starts[i]."""
    import numpy as np

    if isinstance(user_starts, (str, bytes)) or not hasattr(user_starts, "__iter__"):
        raise TypeError(f"user_starts: expected an iterable of start vectors, got {_type_name(user_starts)}")
    vecs = []
    for i, v in enumerate(user_starts):
        if isinstance(v, (str, bytes)):
            raise TypeError(f"user_starts[{i}]: expected a vector of numbers, got {_type_name(v)}")
        try:
            a = np.asarray(v, dtype=float).ravel()
        except (TypeError, ValueError) as e:
            raise TypeError(f"user_starts[{i}]: expected a vector of numbers ({e})") from None
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(f"user_starts[{i}]: start values must be finite numbers (entry {bad[0]} is {a[bad[0]]})")
        vecs.append(a)
    return vecs


def minima(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike], starts: int = 8, seed: int = 1,
           backends: Optional[Union[str, Sequence[str]]] = None, group_tol: float = 1e-6, box: float = 1.0,
           load_path_steps: int = 10, user_starts: Iterable[Any] = (), barriers: bool = False,
           until_complete: bool = False, max_starts: int = 1024) -> MinimaResult:
    """Distinct solutions from many starts, as `hemicontact minima` (its options by the same names,
    with the same ranges: --starts, --seed, --backends, --group-tol, --box, --load-path-steps,
    --barriers, --until-complete, --max-starts; ``backends`` is a list of names or one str,
    comma-separated as the CLI's; ``user_starts`` are --start's vectors: Γ3 unknowns (u_ν, u_τ)
    node after node, or a full displacement)."""
    s = _scene(scene)
    lim = _core.limits
    n_starts = _integer(starts, "starts", 0, lim["starts"])
    n_seed = _integer(seed, "seed", 0, lim["seed"])
    names = [] if backends is None else _names(backends, "backends")
    tol = _positive(group_tol, "group_tol")
    half_width = _positive(box, "box")
    steps = _integer(load_path_steps, "load_path_steps", 0, lim["load_path_steps"])
    vecs = _starts(user_starts)
    flags = [_flag(barriers, "barriers"), _flag(until_complete, "until_complete")]
    cap = _integer(max_starts, "max_starts", n_starts if flags[1] else 1, lim["starts"])
    with _Keywords():
        out = _core.minima(s._s, [], n_starts, n_seed, names, tol, half_width, steps, vecs, flags[0], flags[1], cap)
    return MinimaResult(out["report"], [Result(r) for r in out["solutions"]])


def converge(scene: Union[Scene, Mapping[str, Any], str, _os.PathLike],
             levels: Union[str, Sequence[int]] = "4,8,...,128", reference: int = 256) -> Dict[str, Any]:
    """The mesh-convergence study of `hemicontact converge`: solves n = reference, then each level
    (each must divide it); returns the dict of convergence.json (errors, orders, rate fit).
    ``levels`` is the CLI's text ("4,8,...,128") or a list of integers (floats are refused)."""
    s = _scene(scene)
    top = _core.limits["level"]
    if isinstance(levels, str):
        with _Keywords():
            lv = _core.parse_levels(levels)
    elif isinstance(levels, (list, tuple)) or _is_numpy(levels):
        lv = [_integer(n, f"levels[{i}]", 1, top) for i, n in enumerate(list(levels))]
        if not lv:
            raise ValueError("levels: no level given")
    else:
        raise TypeError(f"levels: expected a str such as \"4,8,...,128\" or a list of integers, "
                        f"got {_type_name(levels)}")
    ref = _integer(reference, "reference", 1, top)
    with _Keywords():
        return _core.converge(s._s, [], lv, ref)


def backends() -> Dict[str, str]:
    """The NLP backends compiled in, name -> description (`hemicontact backends`)."""
    return dict(_core.backends())


def random_scene(base: Scene, seed: int, n_min: int = 8, n_max: int = 24) -> Scene:
    """Scene ``seed`` of the random default-settings study (include/hemicontact/studies/random_scenes.hpp) as
    changes to ``base`` (problems/sofonea2017-fig2.json): its physics, mesh and loads drawn,
    every solver setting at its default. ``base`` is not changed."""
    if not isinstance(base, Scene):
        raise TypeError(f"base: expected a Scene, got {_type_name(base)}")
    top = _core.limits["level"]
    lo = _integer(n_min, "n_min", 1, top)
    hi = _integer(n_max, "n_max", lo, top)
    s = base.copy()
    s.set(*_core.random_scene_assignments(_integer(seed, "seed", 0, _core.limits["seed"]), lo, hi))
    return s
