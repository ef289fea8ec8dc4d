"""Fast-path rules of the package's node kinds (see `implicit.evaluate.tape`).

Each rule emits the operations that compute what the node's ``_evaluate``
computes, in the same order of floating-point operations where it can; the
tests hold the two to 1e-12.  Rules for kinds of other modules are
registered only when those modules import.
"""

from __future__ import annotations

import numpy as np

from ..csg import (Complement, Difference, Intersection, SmoothDifference, SmoothIntersection,
                  SmoothUnion, Union)
from ..modifiers import Offset, Shell
from ..families import FamilyInstance
from ..primitives import Box, Capsule, Cone, Cylinder, Ellipsoid, HalfSpace, Sphere, Torus
from .tape import KernelSource, register_rule
from ..transforms import Affine

__all__: list[str] = []


def _local(gen: KernelSource, coords, centre, frame=None) -> list[int]:
    """Registers of ``frame @ (p - centre)`` (or ``p - centre``).

    Zero terms are left out and unit rows become copies: ``x - 0`` and
    ``0 * a + 1 * b`` are exact in floating point, so the values stay those
    of numpy's full product.
    """
    d = [coords[i] if centre[i] == 0.0 else gen.op("subk", coords[i], gen.const(centre[i]))
         for i in range(3)]
    if frame is None:
        return d
    frame = np.asarray(frame, dtype=np.float64)
    out = []
    for r in range(3):
        terms = [(i, frame[r, i]) for i in range(3) if frame[r, i] != 0.0]
        if len(terms) == 1 and terms[0][1] == 1.0:
            out.append(d[terms[0][0]])
        elif len(terms) == 1 and terms[0][1] == -1.0:
            out.append(gen.op("neg", d[terms[0][0]]))
        elif not terms:
            out.append(gen.op("fill", gen.const(0.0)))
        else:
            acc = gen.op("mulk", d[terms[0][0]], gen.const(terms[0][1]))
            for i, f in terms[1:]:
                gen.op("madk", d[i], acc, gen.const(f), into=acc)
            out.append(acc)
    return out


@register_rule(HalfSpace)
def _halfspace(node, gen, coords):
    n = gen.consts_of(node._n)
    acc = gen.op("mulk", coords[0], n[0])
    gen.op("madk", coords[1], acc, n[1], into=acc)
    gen.op("madk", coords[2], acc, n[2], into=acc)
    return gen.op("subk", acc, gen.const(node._d), into=acc)


@register_rule(Sphere)
def _sphere(node, gen, coords):
    d = _local(gen, coords, node._c)
    return gen.op("subk", gen.op("hyp3", *d), gen.const(node._r))


@register_rule(Box)
def _box(node, gen, coords):
    # One fused operation; the same arithmetic, in the same order, as
    # abs, subk, maxk, hyp3, max, mink, add, subk.
    d = _local(gen, coords, node._c)
    k = gen.consts_of(np.append(node._h, node._rr))[0]
    return gen.op("box", *d, k)


@register_rule(Cylinder)
def _cylinder(node, gen, coords):
    # One fused operation: hyp2, subk, abs, subk, maxk, maxk, hyp2, max, mink, add.
    lx, ly, lz = _local(gen, coords, node._c, node._frame)
    k = gen.const(node._r)
    gen.const(node._hh)  # k + 1
    return gen.op("cylinder", lx, ly, lz, k)


@register_rule(Cone)
def _cone(node, gen, coords):
    lx, ly, lz = _local(gen, coords, node._c, node._frame)
    hh, r1, r2 = node._hh, node._r1, node._r2
    k2x, k2y = r2 - r1, 2.0 * hh
    c_hh, c_r2 = gen.const(hh), gen.const(r2)
    sel = gen.const(r1)
    gen.const(r2)  # sel + 1
    zero, one = gen.const(0.0), gen.const(1.0)
    qx = gen.op("hyp2", lx, ly)
    qy = gen.op("subk", lz, c_hh)
    cax = gen.op("sub", qx, gen.op("min", qx, gen.op("selneg", qy, sel)))
    cay = gen.op("subk", gen.op("abs", qy), c_hh)
    u = gen.op("mulk", gen.op("ksub", qx, c_r2), gen.const(k2x))
    u = gen.op("madk", gen.op("ksub", qy, c_hh), u, gen.const(k2y), into=u)
    t = gen.op("divk", u, gen.const(k2x * k2x + k2y * k2y), into=u)
    t = gen.op("mink", gen.op("maxk", t, zero, into=t), one, into=t)
    cbx = gen.op("madk", t, gen.op("subk", qx, c_r2), gen.const(k2x))
    cby = gen.op("madk", t, gen.op("subk", qy, c_hh), gen.const(k2y))
    v = gen.op("sqrtmin", cax, cay, cbx, cby)
    return gen.op("negif2", v, cbx, cay, into=v)


@register_rule(Torus)
def _torus(node, gen, coords):
    lx, ly, lz = _local(gen, coords, node._c, node._frame)
    a = gen.op("subk", gen.op("hyp2", lx, ly), gen.const(node._R))
    return gen.op("subk", gen.op("hyp2", a, lz), gen.const(node._r))




def _ellipsoid(node, gen, coords):
    # ((p - c) / r, its norm - 1) * min(r), as Ellipsoid._evaluate.
    d = _local(gen, coords, node._c)
    r = gen.consts_of(node._r)
    q = [gen.op("divk", d[i], r[i]) for i in range(3)]
    v = gen.op("subk", gen.op("hyp3", *q), gen.const(1.0))
    return gen.op("mulk", v, gen.const(node._rmin), into=v)


def _capsule(node, gen, coords):
    # w = p - a; t = clip(w . ab / |ab|^2, 0, 1); |w - t ab| - r.
    w = _local(gen, coords, node._a)
    if node._ab2 > 0.0:
        ab = node._ab
        t = gen.op("mulk", w[0], gen.const(ab[0]))
        gen.op("madk", w[1], t, gen.const(ab[1]), into=t)
        gen.op("madk", w[2], t, gen.const(ab[2]), into=t)
        gen.op("divk", t, gen.const(node._ab2), into=t)
        gen.op("mink", gen.op("maxk", t, gen.const(0.0), into=t), gen.const(1.0), into=t)
        w = [gen.op("madk", t, w[i], gen.const(-ab[i])) for i in range(3)]
    return gen.op("subk", gen.op("hyp3", *w), gen.const(node._r))


def _family(node, gen, coords):
    # An instance evaluates its built tree.
    return gen.node(node.children[0], coords)


for _cls, _rule in ((Ellipsoid, _ellipsoid), (Capsule, _capsule), (FamilyInstance, _family)):
    register_rule(_cls)(_rule)


def _sharp(node, gen, coords, start: float, combine: str, negate_tools: bool = False) -> int:
    """``acc = start``, then ``acc = combine(acc, operand)`` per operand."""
    acc = gen.op("fill", gen.const(start))
    for i, child in enumerate(node.children):
        gen.open_flag(node, i)
        v = gen.node(child, coords)
        gen.op("maxneg" if negate_tools and i > 0 else combine, acc, v, into=acc)
        gen.close_flag()
    return acc


def _smooth(node, gen, coords, sign_acc: float, sign_child: float) -> int:
    """Fold ``acc = s_a * smin(s_a * acc, s_c * child, k)`` over the operands."""
    k = node.blend
    acc = gen.reg()
    first = gen.node(node.children[0], coords)
    gen.op("mulk", first, gen.const(1.0), into=acc)
    c_half, c_k, c_one = gen.const(0.5), gen.const(k), gen.const(1.0)
    zero = gen.const(0.0)
    for i, child in enumerate(node.children[1:], start=1):
        gen.open_flag(node, i)
        v = gen.node(child, coords)
        a = acc if sign_acc > 0 else gen.op("neg", acc)
        b = v if sign_child > 0 else gen.op("neg", v)
        # h = clip(0.5 + 0.5 * (b - a) / k, 0, 1)
        h = gen.op("mulk", gen.op("sub", b, a), c_half)
        gen.op("divk", h, c_k, into=h)
        gen.op("addk", h, c_half, into=h)
        gen.op("mink", gen.op("maxk", h, zero, into=h), c_one, into=h)
        # b + (a - b) * h - k * h * (1 - h)
        s = gen.op("add", b, gen.op("mul", gen.op("sub", a, b), h))
        w = gen.op("mul", gen.op("mulk", h, c_k), gen.op("ksub", h, c_one))
        gen.op("sub", s, w, into=s)
        if sign_acc > 0:
            gen.op("mulk", s, c_one, into=acc)
        else:
            gen.op("neg", s, into=acc)
        gen.close_flag()
    return acc


@register_rule(Union, prune="min")
def _union(node, gen, coords):
    return _sharp(node, gen, coords, np.inf, "min")


@register_rule(Intersection, prune="max")
def _intersection(node, gen, coords):
    return _sharp(node, gen, coords, -np.inf, "max")


@register_rule(Difference, prune="diff")
def _difference(node, gen, coords):
    return _sharp(node, gen, coords, -np.inf, "max", negate_tools=True)


@register_rule(SmoothUnion, prune="smin")
def _smooth_union(node, gen, coords):
    return _smooth(node, gen, coords, 1.0, 1.0)


@register_rule(SmoothIntersection, prune="smax")
def _smooth_intersection(node, gen, coords):
    return _smooth(node, gen, coords, -1.0, -1.0)


@register_rule(SmoothDifference, prune="sdiff")
def _smooth_difference(node, gen, coords):
    return _smooth(node, gen, coords, -1.0, 1.0)


@register_rule(Complement)
def _complement(node, gen, coords):
    return gen.op("neg", gen.node(node.children[0], coords))


@register_rule(Offset)
def _offset(node, gen, coords):
    return gen.op("subk", gen.node(node.children[0], coords), gen.const(node.params["distance"]))


@register_rule(Shell)
def _shell(node, gen, coords):
    v = gen.op("abs", gen.node(node.children[0], coords))
    return gen.op("subk", v, gen.const(0.5 * node.params["thickness"]), into=v)


@register_rule(Affine)
def _affine(node, gen, coords):
    local = _local(gen, coords, node._offset, node._inv)
    parent = gen.frame(coords)
    if parent is not None and tuple(local) != tuple(coords):
        m, b = parent
        gen.set_frame(local, node._inv @ m, node._inv @ (b - node._offset))
    gen.map_points(local, coords, lambda q, node=node: (q - node._offset) @ node._inv.T)
    v = gen.node(node.children[0], tuple(local))
    if node._factor == 1.0:
        return v
    return gen.op("mulk", v, gen.const(node._factor))
