"""The client's share of the work: the lattice, the octree down to bricks, and the tasks' parameters.

A brick is an octree cell of ``brick`` voxels per side (a power of two and a
multiple of the meshing block).  The client classifies the octree down to the
bricks' level (a few thousand boxes at most) and hands every BOUNDARY brick to
a task; the tasks classify the levels below, sample, mesh and refine inside
their brick.  A task's parameters are plain data: the solid travels as its
JSON tree, never as a pickled closure.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..cells.lattice import descend, make_lattice
from ..meshing import CLASSIFY_CHUNK, DEFAULT_BLOCK, ZERO_NUDGE
from ..meshing.blocks import check_block

__all__ = ["DEFAULT_BRICK", "BrickSpec", "Plan", "plan_bricks", "check_brick"]

#: Voxels per side of the octree cell one task meshes.  At most ``(brick / 2)**3`` cells of two voxels
#: and, slab by slab, ``(brick / block)**2`` blocks are alive in a task: the bound on a worker's memory.
DEFAULT_BRICK = 256


def check_brick(brick, block):
    """`brick` as an int: a power of two from 16 voxels, a multiple of `block`."""
    if isinstance(brick, bool) or not isinstance(brick, (numbers.Integral, np.integer)):
        raise TypeError(f"brick: expected a power of two (voxels per side), got {brick!r}")
    brick = int(brick)
    if brick < 16 or brick & (brick - 1):
        raise ValueError(f"brick: expected a power of two of at least 16 voxels, got {brick}")
    if brick % block:
        raise ValueError(f"brick: expected a multiple of the block ({block} voxels), got {brick}")
    return brick


@dataclass(frozen=True)
class BrickSpec:
    """What every task of one mesh shares (plain data, pickled by value).

    Attributes
    ----------
    json : str
        The solid (clipped to the bounds when the lattice clipped it) as JSON.
    origin : (3,) tuple of float
        Position of lattice node (0, 0, 0).
    voxel_size : float
    shape : (3,) tuple of int
        Lattice cells per axis (padding included).
    bounds : ((3,), (3,)) tuples of float
    level : int
        Octree level of the bricks (``depth - log2(brick)``, at least 0).
    block : int
        Voxels per side of a meshing block.
    refine : bool
    """

    json: str
    origin: tuple
    voxel_size: float
    shape: tuple
    bounds: tuple
    level: int
    block: int
    refine: bool

    @property
    def depth(self) -> int:
        return int(max(0, math.ceil(math.log2(max(max(self.shape), 1)))))

    @property
    def brick_voxels(self) -> int:
        return 1 << (self.depth - self.level)

    @property
    def stride(self) -> int:
        """Node ids ``(x * stride + y) * stride + z``, the same in every task (edge ids ``3 * id + axis``)."""
        return (1 << self.depth) + 2


@dataclass
class Plan:
    """The lattice, the BOUNDARY bricks and the evaluations the client spent classifying them."""

    lattice: object
    spec: BrickSpec
    bricks: np.ndarray
    evaluations: int


def plan_bricks(solid, *, voxel_size=None, resolution=None, bounds=None, refine=True, block=DEFAULT_BLOCK,
                brick=DEFAULT_BRICK) -> Plan:
    """Classify the octree of `solid` down to bricks of `brick` voxels.

    Returns
    -------
    Plan
        ``bricks`` (k, 3) int: the BOUNDARY bricks (octree cells of level
        ``spec.level``), in the order the tasks are numbered; empty when the
        lattice is empty.
    """
    from implicit.serialize import to_json

    block = check_block(block)
    brick = check_brick(brick, block)
    lattice = make_lattice(solid, voxel_size=voxel_size, resolution=resolution, bounds=bounds)
    level = max(lattice.depth - int(math.log2(brick)), 0)
    lo, hi = lattice.bounds
    spec = BrickSpec(json=to_json(lattice.solid), origin=tuple(float(v) for v in lattice.origin),
                     voxel_size=float(lattice.voxel_size), shape=tuple(int(v) for v in lattice.shape),
                     bounds=(tuple(float(v) for v in lo), tuple(float(v) for v in hi)), level=level,
                     block=block, refine=bool(refine))
    if lattice.empty:
        return Plan(lattice, spec, np.empty((0, 3), np.int32), 0)
    # the margin of `spatial.meshing.mesh`'s classification, so the bricks are the cells it keeps
    found = descend(lattice, keep_leaves=False, stop_level=level, progress=False, chunk=CLASSIFY_CHUNK,
                    margin=ZERO_NUDGE * lattice.voxel_size)
    bricks = np.asarray(found["boundary"], dtype=np.int32).reshape(-1, 3)
    # x slowest: neighbouring tasks share faces, and parts come out in a reading order
    order = np.lexsort((bricks[:, 2], bricks[:, 1], bricks[:, 0]))
    return Plan(lattice, spec, bricks[order], int(found["evaluations"]))
