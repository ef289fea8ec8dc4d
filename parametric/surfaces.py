"""Biparametric surfaces: the common base, Coons patches, ruled and bicubic patches.

Tensor-product Bezier, B-spline and NURBS surfaces live in
:mod:`parametric.tensor` and share the :class:`Surface` base defined here.

A surface maps ``(u, v)`` in its rectangular domain to points: ``surface(u, v)``
takes equal-shape (or broadcastable) arrays and returns ``(..., 3)``.
"""

from __future__ import annotations

from .bicubic import BicubicPatch
from .coons import CoonsPatch, RuledSurface
from .surface_base import CORNER_TOL, SEAM_TOL, Surface

__all__ = ["Surface", "CoonsPatch", "RuledSurface", "BicubicPatch", "CORNER_TOL", "SEAM_TOL"]
