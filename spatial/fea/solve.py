"""Run CalculiX (``ccx``) on a deck and read its results.

`run_calculix` runs ``ccx -i JOB`` in the deck's folder, checks the run
(exit status, ``*ERROR`` lines of its output, the ``.frd`` file written)
and returns the results as a `pyvista.UnstructuredGrid` (`read_frd`) with
a short `StaticResult` summary.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import dataclass

import numpy as np

from .frd import read_frd

__all__ = ["calculix_path", "run_calculix", "StaticResult", "summarize"]


def calculix_path():
    """Path of the ``ccx`` executable on the PATH, or None."""
    return shutil.which("ccx")


@dataclass(frozen=True)
class StaticResult:
    """Headline figures of a linear-static result.

    Attributes
    ----------
    max_displacement : float
        Largest displacement magnitude over the nodes.
    max_von_mises : float
        Largest von Mises stress over the nodes (extrapolated nodal values).
    n_nodes, n_elements : int
    frd : str
        The results file.
    """

    max_displacement: float
    max_von_mises: float
    n_nodes: int
    n_elements: int
    frd: str

    def summary(self) -> str:
        """Two lines of text."""
        return (f"max displacement  {self.max_displacement:.6g}\n"
                f"max von Mises     {self.max_von_mises:.6g}")


def summarize(grid, frd="") -> StaticResult:
    """`StaticResult` of a results grid from `read_frd`."""
    disp = np.asarray(grid.point_data["DISP"]) if "DISP" in grid.point_data else np.zeros((grid.n_points, 3))
    vm = np.asarray(grid.point_data["von_mises"]) if "von_mises" in grid.point_data else np.zeros(grid.n_points)
    return StaticResult(max_displacement=float(np.linalg.norm(disp, axis=1).max(initial=0.0)),
                        max_von_mises=float(vm.max(initial=0.0)), n_nodes=int(grid.n_points),
                        n_elements=int(grid.n_cells), frd=os.fspath(frd))


def run_calculix(deck, *, threads: int = 1, timeout: float = 600.0):
    """Solve `deck` (a ``.inp`` file) with CalculiX and read the results.

    Parameters
    ----------
    deck : str or os.PathLike
        The input file; ``JOB.frd``, ``JOB.dat`` and ``JOB.sta`` are written
        next to it.
    threads : int
        ``OMP_NUM_THREADS`` for the solver.
    timeout : float
        Seconds before the run is stopped.

    Returns
    -------
    grid : pyvista.UnstructuredGrid
        See `read_frd`.
    result : StaticResult

    Raises
    ------
    FileNotFoundError
        When ``ccx`` is not on the PATH or `deck` does not exist.
    RuntimeError
        When CalculiX reports an error or writes no results.

    Examples
    --------
    >>> grid, res = run_calculix("beam.inp")          # doctest: +SKIP
    >>> print(res.summary())                          # doctest: +SKIP
    """
    exe = calculix_path()
    if exe is None:
        raise FileNotFoundError("ccx: CalculiX is not on the PATH (Debian package calculix-ccx)")
    deck = os.path.abspath(os.fspath(deck))
    if not deck.lower().endswith(".inp"):
        raise ValueError(f"deck: expected a .inp file, got {deck!r}")
    if not os.path.isfile(deck):
        raise FileNotFoundError(2, "No such file", deck)
    folder, job = os.path.split(deck[:-4])
    frd = os.path.join(folder, job + ".frd")
    if os.path.exists(frd):
        os.unlink(frd)  # a stale result must not pass for this run's
    env = dict(os.environ, OMP_NUM_THREADS=str(int(threads)), CCX_NPROC_EQUATION_SOLVER=str(int(threads)))
    proc = subprocess.run([exe, "-i", job], cwd=folder or ".", env=env, capture_output=True, text=True,
                          timeout=timeout)
    out = proc.stdout + proc.stderr
    errors = [ln.strip() for ln in out.splitlines() if "*ERROR" in ln]
    if proc.returncode != 0 or errors or not os.path.isfile(frd):
        detail = "; ".join(errors[:3]) or out.strip().splitlines()[-1:] or ["no output"]
        raise RuntimeError(f"ccx: the run of {job}.inp failed (exit {proc.returncode}): "
                           f"{detail if isinstance(detail, str) else detail[0]}")
    grid = read_frd(frd)
    return grid, summarize(grid, frd)
