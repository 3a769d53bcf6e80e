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

import os
from collections import namedtuple

# The annotations are not evaluated (postponed, PEP 563) and the type checkers read __init__.pyi:
# typing is imported for them only, which keeps it (~5 ms) out of a script's start.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

from . import _hemicontact as _core
from ._hemicontact import HemicontactError, SceneError, __version__

__all__ = [
    "Scene", "Result", "Certificate", "MinimaResult", "SceneError", "HemicontactError",
    "solve", "adapt", "minima", "converge", "backends", "random_scene", "__version__",
]


class Scene:
    """A scene: a scene file (or a dict in the same format) and the ``--set`` changes made to it.

    ``scene["mesh.n"] = 128`` is ``--set mesh.n=128``: the whole scene is validated again with the
    CLI's checks, and a bad key or value raises :class:`SceneError` leaving the scene unchanged.
    ``scene["mesh.nx"]`` reads a value of the effective scene (every default filled in).
    """

    def __init__(self, scene: Union[Mapping[str, Any], "Scene"], directory: Optional[str] = None):
        """Validate a scene given as a dict (the JSON of a scene file).

        ``directory`` is where relative paths in it (``mesh.file``) are taken from (default: the
        current folder). A :class:`Scene` is copied.
        """
        if isinstance(scene, Scene):
            self._s = scene._s.copy()
        else:
            self._s = _core._Scene.from_dict(dict(scene), directory if directory is not None else ".")

    @classmethod
    def load(cls, path: Union[str, os.PathLike], *assignments: str) -> "Scene":
        """Read a scene file, applying ``--set``-style ``"key=value"`` assignments in order."""
        self = cls.__new__(cls)
        self._s = _core._Scene.load(os.fspath(path))
        if assignments:
            self._s.apply(list(assignments))
        return self

    def __getitem__(self, key: str) -> Any:
        """The value at a dotted key of the effective scene (``KeyError`` when absent)."""
        return self._s.get(key)

    def __setitem__(self, key: str, value: Any) -> None:
        """``--set key=value`` with the value as JSON; raises :class:`SceneError` if invalid."""
        self._s.set(key, value)

    def set(self, *assignments: str) -> "Scene":
        """Apply ``--set`` assignments as the CLI takes them (``"mesh.type=gmsh"``); returns self."""
        self._s.apply(list(assignments))
        return self

    def copy(self) -> "Scene":
        """An independent copy (changes to it leave this scene as it is)."""
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


class Certificate(namedtuple("Certificate", "passed max_residual tol residuals")):
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

    def write(self, folder: Union[str, os.PathLike], force: bool = False) -> None:
        """Write what `hemicontact solve --out folder` writes: report.json, solution.vtu and
        gamma3.csv (as the scene's output block says; adapt_levels.json for an adaptive solve).
        The folder's rules are the CLI's: results of an earlier run are replaced only with force."""
        self._r.write(os.fspath(folder), force)

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

    def export(self, path: Union[str, os.PathLike], **kwargs: Any) -> None:
        """Write the mesh and u with meshio in the format its extension names (.vtu, .xdmf, .msh, ...)."""
        self.to_meshio().write(os.fspath(path), **kwargs)

    def __repr__(self) -> str:
        return f"Result(energy={self.energy!r}, ok={self.ok}, solved_by={self.solved_by!r})"


def _scene(scene: Union[Scene, Mapping[str, Any], str, os.PathLike]) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    return Scene(scene)


def _assignments(backend: Optional[str], options: Mapping[str, Any]) -> List[str]:
    # solve(scene, tol=1e-12, fixed_point__tol_u=1e-9): solver.tol, solver.fixed_point.tol_u.
    import json

    out = []
    if backend is not None:
        out.append("solver.backend=" + json.dumps(backend))
    for key, value in options.items():
        out.append("solver." + key.replace("__", ".") + "=" + json.dumps(value))
    return out


def solve(scene: Union[Scene, Mapping[str, Any], str, os.PathLike], backend: Optional[str] = None,
          **options: Any) -> Result:
    """Solve a scene as `hemicontact solve` does (adaptively when adapt.target_error is set).

    ``backend`` is ``--backend``; each keyword is a ``solver.`` key, ``__`` for a dot:
    ``solve(scene, tol=1e-12, fixed_point__tol_u=1e-9)``. The scene itself is not changed.
    Raises :class:`SceneError` for bad input; a solve that does not converge or certify returns
    a Result with ``ok`` False (as the CLI's exit codes 3 and 4).
    """
    return Result(_core.solve(_scene(scene)._s, _assignments(backend, options)))


def adapt(scene: Union[Scene, Mapping[str, Any], str, os.PathLike], target_error: float = 0.01,
          backend: Optional[str] = None, **options: Any) -> Result:
    """The adaptive solve (`hemicontact solve` with adapt.target_error): refine until the relative
    error estimate is at most ``target_error``; the Result is the final mesh's, its report holds
    the levels under "adapt"."""
    import json

    extra = _assignments(backend, options) + ["adapt.target_error=" + json.dumps(target_error)]
    return Result(_core.solve(_scene(scene)._s, extra))


class MinimaResult:
    """`hemicontact minima`'s answer: ``report`` is the dict of minima.json, ``solutions`` a
    :class:`Result` per distinct solution, lowest energy first (as solution_<k>.vtu)."""

    def __init__(self, report: Dict[str, Any], solutions: List[Result]):
        self.report = report
        self.solutions = solutions

    def __repr__(self) -> str:
        return f"MinimaResult({len(self.solutions)} distinct solutions, {len(self.report.get('runs', []))} runs)"


def minima(scene: Union[Scene, Mapping[str, Any], str, os.PathLike], starts: int = 8, seed: int = 1,
           backends: Optional[Sequence[str]] = None, group_tol: float = 1e-6, box: float = 1.0,
           load_path_steps: int = 10, user_starts: Iterable[Any] = ()) -> MinimaResult:
    """Distinct solutions from many starts, as `hemicontact minima` (its options by the same names:
    --starts, --seed, --backends, --group-tol, --box, --load-path-steps; ``user_starts`` are
    --start's vectors: Γ3 unknowns (u_ν, u_τ) node after node, or a full displacement)."""
    if not 0 <= starts <= 10000:
        raise SceneError(f"--starts: expected an integer from 0 to 10000, got '{starts}'")
    if group_tol <= 0 or box <= 0:
        raise SceneError("--group-tol and --box: expected positive numbers")
    import numpy as np

    vecs = [np.asarray(v, dtype=float).ravel() for v in user_starts]
    out = _core.minima(_scene(scene)._s, [], starts, seed, list(backends or []), group_tol, box,
                       load_path_steps, vecs)
    return MinimaResult(out["report"], [Result(s) for s in out["solutions"]])


def converge(scene: Union[Scene, Mapping[str, Any], str, os.PathLike],
             levels: Union[str, Sequence[int]] = "4,8,...,128", reference: int = 256) -> Dict[str, Any]:
    """The mesh-convergence study of `hemicontact converge`: solves n = reference, then each level
    (each must divide it); returns the dict of convergence.json (errors, orders, rate fit)."""
    lv = _core.parse_levels(levels) if isinstance(levels, str) else [int(n) for n in levels]
    return _core.converge(_scene(scene)._s, [], lv, int(reference))


def backends() -> Dict[str, str]:
    """The NLP backends compiled in, name -> description (`hemicontact backends`)."""
    return dict(_core.backends())


def random_scene(base: Scene, seed: int, n_min: int = 8, n_max: int = 24) -> Scene:
    """Scene ``seed`` of the random default-settings study (tests/stress/random_scenes.hpp) as
    changes to ``base`` (problems/sofonea2017-fig2.json): its physics, mesh and loads drawn,
    every solver setting at its default. ``base`` is not changed."""
    s = base.copy()
    s.set(*_core.random_scene_assignments(seed, n_min, n_max))
    return s
