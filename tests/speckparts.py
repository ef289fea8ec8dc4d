"""Parts with many features thinner than the lattice (shared by the speck tests)."""

import numpy as np

import implicit as I


def many_specks(h, n=100):
    """A box and `n` spheres of radius 0.3 h scattered five voxels apart above it (z about 1)."""
    rng = np.random.default_rng(3)
    side = int(np.ceil(np.sqrt(n)))
    g = (np.stack(np.meshgrid(np.arange(side), np.arange(side), indexing="ij"), -1).reshape(-1, 2)[:n] * 5 * h
         - 2.5 * h * (side - 1))
    at = np.column_stack([g + rng.uniform(-0.5 * h, 0.5 * h, g.shape), 1.0 + rng.uniform(-0.5 * h, 0.5 * h, n)])
    return I.union(I.box(1.0), *[I.sphere(0.3 * h, tuple(p)) for p in at])
