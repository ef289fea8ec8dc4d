"""Hypothesis strategies of small random CSG solids, shared by the cells and meshing tests."""

import numpy as np
from hypothesis import strategies as st

from implicit import box, cylinder, sphere, torus


def _random_solid(draw):
    kind = draw(st.sampled_from(["sphere", "box", "torus", "cylinder"]))
    c = np.array([draw(st.floats(-0.3, 0.3)) for _ in range(3)])
    if kind == "sphere":
        s = sphere(draw(st.floats(0.3, 1.0)), center=c)
    elif kind == "box":
        s = box([draw(st.floats(0.3, 1.5)) for _ in range(3)], center=c)
    elif kind == "torus":
        s = torus(draw(st.floats(0.5, 0.9)), draw(st.floats(0.1, 0.4))).translate(c)
    else:
        s = cylinder(draw(st.floats(0.2, 0.6)), draw(st.floats(0.5, 1.5)),
                     axis=[draw(st.floats(-1, 1)), draw(st.floats(-1, 1)), 1.0]).translate(c)
    return s


@st.composite
def solids(draw):
    a = _random_solid(draw)
    op = draw(st.sampled_from(["none", "union", "difference", "intersection"]))
    if op == "none":
        return a
    b = _random_solid(draw)
    return {"union": a | b, "difference": a - b, "intersection": a & (b | sphere(0.2))}[op]
