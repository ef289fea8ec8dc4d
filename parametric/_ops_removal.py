"""B-spline algorithms on raw arrays: knot removal (A5.8), degree elevation by Bezier
decomposition (`elevate`), and the exact derivative of a rational curve (see `parametric._ops_core`)."""

from __future__ import annotations

import numpy as np

from .basis import (KNOT_TOL)


from ._ops_core import (bezier_segments, clamp, distinct_interior, domain, elevate_collocation,  # noqa: F401
                        elevate_periodic, eval_derivs, fold_collocate, n_ctrl, periodic_count,
                        periodic_knots_from)

def remove_knot(U, p, P, u, num, tol):
    """Remove interior knot ``u`` up to ``num`` times (A5.8).

    A removal is accepted when the curve moves by at most ``tol`` (checked on the
    control points, which bounds the curve change by the convex hull property).

    Returns
    -------
    (U', P', removed) with ``removed <= num``.
    """
    a, b = domain(U, p)
    if not (a < u < b):
        raise ValueError(f"u must lie strictly inside the domain ({a}, {b}) to be removed, got {u}")
    tolk = KNOT_TOL * max(1.0, float(np.max(np.abs(U))))
    hit = np.nonzero(np.abs(U - u) <= tolk)[0]
    if hit.size == 0:
        raise ValueError(f"u = {u} is not a knot")
    r = int(hit[-1])
    s = hit.size
    u = float(U[r])
    n = P.shape[0] - 1
    m = n + p + 1
    order = p + 1
    fout = (2 * r - s - p) // 2
    last = r - s
    first = r - p
    Pw = P.astype(float).copy()
    temp = np.empty((2 * p + 1,) + P.shape[1:])
    t = 0
    for t in range(num + 1):
        if t == num or t >= s:
            break
        off = first - 1
        temp[0] = Pw[off]
        temp[last + 1 - off] = Pw[last + 1]
        i, j = first, last
        ii, jj = 1, last - off
        while j - i > t:
            alfi = (u - U[i]) / (U[i + order + t] - U[i])
            alfj = (u - U[j - t]) / (U[j + order] - U[j - t])
            temp[ii] = (Pw[i] - (1.0 - alfi) * temp[ii - 1]) / alfi
            temp[jj] = (Pw[j] - alfj * temp[jj + 1]) / (1.0 - alfj)
            i += 1
            ii += 1
            j -= 1
            jj -= 1
        if j - i < t:
            ok = np.max(np.abs(temp[ii - 1] - temp[jj + 1])) <= tol
        else:
            alfi = (u - U[i]) / (U[i + order + t] - U[i])
            ok = np.max(np.abs(Pw[i] - (alfi * temp[ii + t + 1] + (1.0 - alfi) * temp[ii - 1]))) <= tol
        if not ok:
            break
        i, j = first, last
        while j - i > t:
            Pw[i] = temp[i - off]
            Pw[j] = temp[j - off]
            i += 1
            j -= 1
        first -= 1
        last += 1
    else:
        t = num
    if t == 0:
        return U.copy(), P.copy(), 0
    Un = np.concatenate([U[:r - t + 1], U[r + 1:]])
    j = fout
    i = j
    for k in range(1, t):
        if k % 2 == 1:
            i += 1
        else:
            j -= 1
    keep = np.concatenate([Pw[:j], Pw[i + 1:n + 1]])
    assert keep.shape[0] == n + 1 - t and Un.size == m + 1 - t
    return Un, keep, t


def bezier_elevate(Q, t):
    """Raise a Bezier control array ``(p + 1, ...)`` by ``t`` degrees (eq. 5.36)."""
    for _ in range(t):
        n = Q.shape[0] - 1
        i = (np.arange(1, n + 1) / (n + 1.0)).reshape((-1,) + (1,) * (Q.ndim - 1))
        Q = np.concatenate([Q[:1], i * Q[:-1] + (1.0 - i) * Q[1:], Q[-1:]])
    return Q


def elevate_by_decomposition(U, p, P, t, tol=None):
    """Degree elevation: Bezier decomposition, Bezier elevation, knot removal.

    Each distinct interior knot of multiplicity ``m`` ends with multiplicity
    ``m + t`` (The NURBS Book, section 5.5); the removals are exact in exact
    arithmetic, so ``tol`` only absorbs rounding (default ``1e-9`` of the control
    polygon's size).
    """
    segs = bezier_segments(U, p, P)
    q = p + t
    vals, counts = distinct_interior(clamp(U, p, P)[0], p)
    parts = [bezier_elevate(Q, t) for _, _, Q in segs]
    ctrl = np.concatenate([parts[0]] + [Q[1:] for Q in parts[1:]])
    a, b = segs[0][0], segs[-1][1]
    Un = np.concatenate([np.full(q + 1, a), np.repeat(vals, q), np.full(q + 1, b)])
    if tol is None:
        flat = P.reshape(P.shape[0], -1)
        tol = 1e-9 * max(1.0, float(np.max(np.ptp(flat, axis=0))))
    for v, mlt in zip(vals, counts):
        want = p - mlt
        if want:
            Un, ctrl, done = remove_knot(Un, q, ctrl, float(v), want, tol)
            if done != want:
                raise ArithmeticError(f"knot {v} removal stopped after {done} of {want}")
    return Un, ctrl


# --------------------------------------------------------------------------- rational derivative

def bezier_product(F, G):
    """Bernstein coefficients of the product of two Bezier polynomials.

    ``F`` is ``(S, m + 1, ...)`` and ``G`` is ``(S, n + 1, ...)`` (``S`` pieces,
    trailing shapes broadcast); the product has degree ``m + n``:
    ``H_k = sum_{i + j = k} C(m, i) C(n, j) / C(m + n, k) F_i G_j``.
    """
    from scipy.special import comb  # local: scipy.special costs 0.1 s to import

    m, n = F.shape[1] - 1, G.shape[1] - 1
    shape = np.broadcast_shapes(F.shape[2:], G.shape[2:])
    H = np.zeros((F.shape[0], m + n + 1) + shape)
    for i in range(m + 1):
        for j in range(n + 1):
            H[:, i + j] += (comb(m, i) * comb(n, j) / comb(m + n, i + j)) * F[:, i] * G[:, j]
    return H


def rational_derivative(U, p, Pw, tol):
    """Exact derivative of a rational curve as homogeneous control of degree ``2 p``.

    On each Bezier piece of ``C = A / w`` (``Pw = (A, w)``), ``C' = (A' w - A w') / w^2``:
    the numerator (degree ``2 p - 1``, elevated once) and ``w^2`` (degree ``2 p``)
    are built with Bezier products, so ``(A' w - A w', w^2)`` are the homogeneous
    control points of the derivative. Pieces meet with multiplicity ``2 p``; a
    knot of multiplicity ``m < p`` is then removed ``p - m - 1`` times (exact:
    the derivative is ``C^(p-m-1)`` there), leaving multiplicity ``p + m + 1``.

    Raises
    ------
    ValueError
        If the derivative jumps at a knot of multiplicity ``p`` (it is then no
        single curve).

    A wrapped periodic curve (:func:`periodic_count`) whose knots are all of
    multiplicity below ``p`` gives a periodic derivative: the homogeneous
    ``(A' w - A w', w^2)`` is collocated on the folded periodic basis of
    degree ``2 p`` with multiplicities ``p + m + 1``.

    Returns
    -------
    (U', Qw) with ``Qw`` of shape ``(n', dim + 1)``.
    """
    k = periodic_count(U, p, Pw)
    if k:
        a, b = domain(U, p)
        inside = U[(U >= a) & (U < b)]
        vals, counts = np.unique(inside, return_counts=True)
        if np.all(counts < p):
            def homogeneous(x):
                H = eval_derivs(U, p, Pw, x, 1)
                A, A1, w, w1 = H[:, 0, :-1], H[:, 1, :-1], H[:, 0, -1:], H[:, 1, -1:]
                return np.concatenate([A1 * w - A * w1, w * w], axis=1)

            Un = periodic_knots_from(vals, counts + p + 1, 2 * p, a, b)
            K = int(np.sum(counts + p + 1))
            return Un, fold_collocate(homogeneous, Un, 2 * p, K)
    segs = bezier_segments(U, p, Pw)
    a = np.array([s[0] for s in segs])
    b = np.array([s[1] for s in segs])
    Q = np.stack([s[2] for s in segs])                    # (S, p + 1, D + 1)
    A, w = Q[..., :-1], Q[..., -1]
    scale = (p / (b - a))[:, None, None]
    dA = scale * np.diff(A, axis=1)                        # (S, p, D)
    dw = scale[..., 0] * np.diff(w, axis=1)                # (S, p)
    num = bezier_product(dA, w[..., None]) - bezier_product(A, dw[..., None])
    num = bezier_elevate(np.moveaxis(num, 1, 0), 1)        # (2p + 1, S, D)
    num = np.moveaxis(num, 0, 1)
    den = bezier_product(w, w)                             # (S, 2p + 1)
    H = np.concatenate([num, den[..., None]], axis=-1)     # (S, 2p + 1, D + 1)
    q = 2 * p
    # joints: the end of piece s must meet the start of piece s + 1
    ends = H[:-1, -1, :-1] / H[:-1, -1, -1:]
    starts = H[1:, 0, :-1] / H[1:, 0, -1:]
    size = max(1.0, float(np.max(np.abs(H[..., :-1] / H[..., -1:]))))
    jump = np.linalg.norm(ends - starts, axis=-1) if len(segs) > 1 else np.zeros(0)
    vals, counts = distinct_interior(clamp(U, p, Pw)[0], p)
    bad = jump > tol * size
    if np.any(bad):
        k = int(np.nonzero(bad)[0][0])
        raise ValueError(f"the derivative jumps at knot u={b[k]} (multiplicity {p}, "
                         f"jump {jump[k]:.3g}); it is not one curve")
    ctrl = np.concatenate([H[0]] + [H[s, 1:] for s in range(1, len(segs))])
    Un = np.concatenate([np.full(q + 1, a[0]), np.repeat(b[:-1], q), np.full(q + 1, b[-1])])
    rtol = tol * max(1.0, float(np.max(np.abs(ctrl))))
    for v, mlt in zip(vals, counts):
        want = p - int(mlt) - 1
        if want > 0:
            Un, ctrl, _ = remove_knot(Un, q, ctrl, float(v), want, rtol)
    return Un, ctrl


def elevate(U, p, P, t):
    """Degree elevation by ``t`` (decomposition + Bezier elevation + knot removal).

    A wrapped periodic spline (:func:`periodic_count`) stays periodic
    (:func:`elevate_periodic`). Falls back to :func:`elevate_collocation` if
    rounding stops a removal.
    """
    k = periodic_count(U, p, P)
    if k:
        return elevate_periodic(U, p, P, t, k)
    try:
        return elevate_by_decomposition(U, p, P, t)
    except ArithmeticError:
        return elevate_collocation(U, p, P, t)
