"""A wireframe is ambiguous: three different solids with exactly one wireframe.

The block ``3 x 2 x 3`` with a through-hole of radius 0.6 along y has, as its
wireframe, the block's twelve edges and the two circles where the hole meets
the front and back faces.  Three solids have exactly those feature edges:

* ``straight``: the block minus a cylinder (a drilled hole);
* ``barrel``: the block minus a sphere zone (a bore that widens inside, the
  sphere of radius ``sqrt(r^2 + 1)`` cut by the front and back planes);
* ``waisted``: the block minus the inner side of a torus (a bore that narrows
  inside, an hourglass).

A bore with corners along its length (a slot with flat walls) cannot be read
other ways: its long edges would change with the walls.  Orthogonal solids
made of the cells of one grid are even fixed by their edges (toggling cells
changes the edges around them), so the ambiguity needs a face without edges
of its own: here the smooth bore.

Examples
--------
>>> from spatial.compare.ambiguity import ambiguous_solids
>>> sorted(ambiguous_solids())
['barrel', 'straight', 'waisted']
"""

from __future__ import annotations

import math

import numpy as np

from implicit import box, cylinder, sphere, torus

from ..files import atomic_write

__all__ = ["ambiguous_solids", "wireframe_segments", "wire_matches", "BLOCK", "HOLE_RADIUS", "picture"]

#: Block size (x, y, z) and the radius of the hole where it meets the faces y = +/- 1.
BLOCK = (3.0, 2.0, 3.0)
HOLE_RADIUS = 0.6
#: Tube radius of the torus whose inner side makes the waisted bore.
WAIST_TUBE = 1.5


def ambiguous_solids() -> dict:
    """``{"straight", "barrel", "waisted"}``: three solids with one wireframe."""
    y = (0.0, 1.0, 0.0)
    half = BLOCK[1] / 2
    block = box(BLOCK)
    r = HOLE_RADIUS
    slab = box((BLOCK[0] + 1, BLOCK[1], BLOCK[2] + 1))  # the through-length, |y| <= 1
    straight = block - cylinder(r, 2 * BLOCK[1], axis=y)
    barrel = block - (sphere(math.sqrt(r * r + half * half)) & slab)
    major = r + math.sqrt(WAIST_TUBE ** 2 - half * half)
    core = (cylinder(major, BLOCK[1], axis=y) & slab) - torus(major, WAIST_TUBE, axis=y)
    waisted = block - core
    return {"straight": straight, "barrel": barrel, "waisted": waisted}


def wireframe_segments(n_circle=96) -> np.ndarray:
    """The shared wireframe (m, 2, 3): the block's edges and the two hole circles."""
    hx, hy, hz = (s / 2 for s in BLOCK)
    corners = np.array([[x, y, z] for x in (-hx, hx) for y in (-hy, hy) for z in (-hz, hz)])
    segs = [(corners[i], corners[j]) for i in range(8) for j in range(i + 1, 8)
            if np.count_nonzero(corners[i] != corners[j]) == 1]
    t = np.linspace(0, 2 * np.pi, n_circle + 1)
    for y in (-hy, hy):
        ring = np.column_stack([HOLE_RADIUS * np.cos(t), np.full_like(t, y), HOLE_RADIUS * np.sin(t)])
        segs += list(zip(ring[:-1], ring[1:]))
    return np.array([[a, b] for a, b in segs], dtype=np.float64)


def _point_segment_distance(p, a, b):
    """Distances (n,) from points to the nearest of segments ``a``, ``b`` (m, 3)."""
    d = b - a
    best = np.full(len(p), np.inf)
    for start in range(0, len(a), 64):  # blocks of segments keep memory at n * 64
        aa, dd = a[start:start + 64], d[start:start + 64]
        length2 = np.maximum(np.einsum("mk,mk->m", dd, dd), 1e-300)  # a segment may shrink to a point
        t = np.clip(np.einsum("nmk,mk->nm", p[:, None, :] - aa[None], dd) / length2, 0, 1)
        q = aa[None] + t[..., None] * dd[None]
        best = np.minimum(best, np.linalg.norm(p[:, None, :] - q, axis=2).min(axis=1))
    return best


def wire_matches(segments, reference, tolerance) -> tuple:
    """``(worst distance of the wire from the reference, worst distance of the reference from the wire)``.

    Both below `tolerance`: the two wireframes are the same curves.
    """
    seg = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 3)
    ref = np.asarray(reference, dtype=np.float64).reshape(-1, 2, 3)
    mid = seg.mean(axis=1)
    out = _point_segment_distance(mid, ref[:, 0], ref[:, 1]).max()
    samples = (ref[:, :1] + np.linspace(0, 1, 5)[None, :, None] * (ref[:, 1:] - ref[:, :1])).reshape(-1, 3)
    cover = _point_segment_distance(samples, seg[:, 0], seg[:, 1]).max()
    del tolerance
    return float(out), float(cover)


def picture(path=None, *, resolution=64, window=(420, 360)):
    """The wireframe beside the three solids (cut open at z = 0 to show the bore); writes a PNG.

    Returns ``{name: (volume, wire_out, wire_cover)}``.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..analysis import mass_properties
    from ..drafting import render
    from ..meshing import mesh
    from .brep import brep

    solids = ambiguous_solids()
    ref = wireframe_segments()
    h = max(BLOCK) / resolution
    fig = plt.figure(figsize=(13, 3.8))
    ax = fig.add_subplot(1, 4, 1, projection="3d")
    for a, b in ref:
        ax.plot(*zip(a, b), color="k", lw=1.2)
    ax.set_box_aspect(BLOCK)
    ax.view_init(elev=22, azim=-60)
    ax.set_axis_off()
    ax.set_title("one wireframe", fontsize=10)
    facts = {}
    for i, (name, solid) in enumerate(solids.items()):
        m = mesh(solid, resolution=resolution, progress=False)
        rep = brep(solid, m)
        facts[name] = (mass_properties(m).volume, *wire_matches(rep.edge_segments, ref, 2 * h))
        half = m.clip_closed_surface(normal=(0, 0, -1), origin=(0, 0, 0))  # keeps z <= 0, capped
        image = render(half, style="shaded", view="iso", window_size=window)
        axi = fig.add_subplot(1, 4, i + 2)
        axi.imshow(image)
        axi.set_axis_off()
        axi.set_title(f"{name} bore: volume {facts[name][0]:.3f}\n(cut open at z = 0)", fontsize=9)
    fig.suptitle("A wireframe is ambiguous: three solids, each with exactly this wireframe", fontsize=11)
    fig.tight_layout()
    if path is not None:
        atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=100, format="png"), ".png")
    plt.close(fig)
    return facts
