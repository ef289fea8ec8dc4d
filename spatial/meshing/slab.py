"""Sampling and meshing one slab of boundary cells (two passes, signs inferred where proven)."""

from __future__ import annotations

import queue
import sys
import threading

import numpy as np

from .saddles import break_ties_marked
from .arrays import ZERO_NUDGE, ZERO_TIE, _evaluate, _nudge, _settle_ties
from .kernels import block_boxes, block_mask_held, count_needed, take_block_held
from .slab_kernels import (blocks_with_ties, first_pass, merged_nodes, nudged_float32, second_pass, slab_blocks,
                           slab_codes, slab_needed, slab_samples)

__all__ = []

# Offsets from a cell's centre node to the other 26 nodes of a cell of 2 voxels, by distance (in h).
_NEIGHBOURS = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)
                        if (i, j, k) != (0, 0, 0)], dtype=np.int64)
_NEIGHBOUR_DIST = np.sqrt((_NEIGHBOURS ** 2).sum(axis=1))

# An empty handoff (the first slab, or one after a gap), and the other empty inputs of the kernels.
_NO_IDS, _NO_VALUES, _NO_SIGNS = np.empty(0, np.int64), np.empty(0, np.float32), np.empty(0, np.int8)
_NO_ROWS, _NO_WHERE = np.empty(0, np.int64), np.empty(0, np.int32)


def _rows_or_none(pair, index_type=np.int32, value_type=np.int8):
    """``(rows (k, 3), values (k,))`` of a ring, or empty ones for None."""
    if pair is None:
        return np.empty((0, 3), index_type), np.empty(0, value_type)
    return pair


_STEPS = {}


def _steps(B):
    """Flat offsets from a node to its 26 neighbours in a block's ``(B+1)^3`` array."""
    if B not in _STEPS:
        n = B + 1
        _STEPS[B] = (_NEIGHBOURS * np.array([n * n, n, 1])).sum(axis=1).astype(np.int64)
    return _STEPS[B]


class _SlabJob:
    """Sample and mesh one slab of cells (x from ``slab * block`` voxels, ``block`` thick).

    The slab's active blocks (those holding cells) are stacked in dense
    ``(nb, block+1, block+1, block+1)`` arrays, so the work follows the
    surface.  Only nodes of the cells are considered, each evaluated at most
    once: nodes on a face shared by two blocks are merged by their integer
    id, and the lower node plane reuses what the previous slab learned about
    its upper plane (`handoff`: sorted ids, values -- NaN when only the sign
    is known -- and signs).
    """

    def __init__(self, solid, origin, h, c, block, slab, stride, lip):
        self.solid, self.origin, self.h, self.c = solid, origin, h, c
        self.B, self.P = block, block // c
        self.slab, self.stride, self.lip = slab, stride, lip
        self.x0 = slab * block
        self.nbz = int(stride) // block + 3  # block keys: by * nbz + bz, the same in every slab
        self.capacity_hint = 1 << 16  # vertices the slab's buffers start with
        self.scratch = None  # a `_Scratch` lent by `run_slabs` (None: fresh arrays)

    # -- the parts -------------------------------------------------------------------------
    def _needed(self, cells):
        """Nodes of the cells, for cells without a ring of known neighbours (`slab_kernels.slab_codes`
        serves cells of 2 voxels): a separable dilation (each axis: repeat c times, OR a shift by one)."""
        c = self.c
        need = cells
        for ax in (1, 2, 3):
            rep = np.repeat(need, c, axis=ax) if c > 1 else need
            shape = list(rep.shape)
            shape[ax] += 1
            grown = np.zeros(shape, dtype=bool)
            lo_sl = [slice(None)] * 4
            hi_sl = [slice(None)] * 4
            lo_sl[ax] = slice(0, -1)
            hi_sl[ax] = slice(1, None)
            grown[tuple(lo_sl)] = rep
            grown[tuple(hi_sl)] |= rep
            need = grown
        return need

    def _thresholds(self):
        """Per neighbour of a sampled node (`_NEIGHBOURS`), the distance to the level past which the
        node's sign is the neighbour's: ``L d h`` (float32 values: a margin for their rounding)."""
        thresholds = np.empty(_NEIGHBOURS.shape[0], dtype=np.float32)
        for d in np.unique(_NEIGHBOUR_DIST):
            thresholds[_NEIGHBOUR_DIST == d] = np.float32(self.lip * d * self.h * (1 + 1e-6))
        return thresholds

    def prepare(self, sc, given, ring, centre_infer, handoff, extra=None):
        """Sample the slab's nodes: ``(cells, values (nb, B+1, B+1, B+1), evaluations, handoff)``,
        what `mesh` takes.  Needs only the previous slab's handoff, not its mesh, so the next slab
        can be prepared while this one is meshed."""
        B, P, c, h, x0, stride = self.B, self.P, self.c, self.h, self.x0, self.stride
        keys, inv, lx, ly, lz, cells = slab_blocks(sc, int(self.slab), int(P), int(self.nbz))
        self.keys, self.nb, self.cl = keys, keys.shape[0], (inv, lx, ly, lz)
        self.bys, self.bzs = np.divmod(keys, self.nbz)
        if c == 2:
            # one compiled call: the codes from the ring, the signs the samples give, the needed count
            code = _take(self.scratch, "code", (self.nb,) + (2 * P + 1,) * 3, np.uint8)
            (ring_idx, ring_sgn), (par_idx, par_sgn) = (_rows_or_none(r) for r in ring)
            extra_idx, extra_val = _rows_or_none(extra, np.int64, np.float32)
            eb, ex, ey, ez, ev, n_need = slab_codes(
                sc, inv, lx, ly, lz, keys, int(self.nbz), int(self.slab), int(P), ring_idx, ring_sgn, par_idx,
                par_sgn, _NO_VALUES if given is None else given, extra_idx, extra_val, bool(centre_infer),
                _steps(B), self._thresholds() if centre_infer else _NO_VALUES, code)
        else:
            code = self._needed(cells).view(np.uint8)
            eb = ex = ey = ez = _NO_ROWS
            ev = _NO_VALUES
            n_need = count_needed(code.reshape(-1))
        # -- the needed nodes as a list, with their values where already sampled -----------------
        # positions within the slab's arrays fit 32 bits: halves the memory of the node lists
        itype = np.int32 if code.size < 2 ** 31 else np.int64
        # (the node lists are lent by the scratch: every kernel below writes all it reads of them)
        flat = _take(self.scratch, "flat", (n_need,), itype)
        s_n = _take(self.scratch, "s_n", (n_need,), np.int8)
        # nodes on a y/z block face or on the lower x plane may be needed twice: merge by id
        maybe = _take(self.scratch, "maybe", (n_need,), np.bool_)
        upper = _take(self.scratch, "upper", (n_need,), np.bool_)
        v_n = _take(self.scratch, "v_n", (n_need,), np.float32)
        # nodes already sampled (never on a block face) hold their values: found through the row of
        # every needed node at its position, written into the slab's samples array (not filled before
        # `slab_samples` below; 32-bit rows fit it)
        sampled = given is not None or eb.shape[0]
        where = (_take(self.scratch, "values", (code.size,), np.float32).view(np.int32) if sampled
                 else _NO_WHERE)
        slab_needed(code.reshape(-1), B, flat, s_n, maybe, upper, inv, lx, ly, lz,
                    _NO_VALUES if given is None else given, eb, ex, ey, ez, ev, where, v_n)
        del where, eb, ex, ey, ez, ev
        y_base = (self.bys * B).astype(np.int64)
        z_base = (self.bzs * B).astype(np.int64)
        # -- the nodes two blocks may share, merged by id; what the previous slab learned of them --
        if handoff is not None and handoff[0] == self.slab - 1 and handoff[1].size:
            pid, pval, psgn = handoff[1], handoff[2], handoff[3]
        else:
            pid, pval, psgn = _NO_IDS, _NO_VALUES, _NO_SIGNS
        origin = np.asarray(self.origin, dtype=np.float64)
        m_idx, ufirst, back, s_u, v_u = merged_nodes(flat, maybe, s_n, B, int(x0), y_base, z_base, int(stride),
                                                     pid, pval, psgn)
        spent = 0

        def sample(pts, k):
            """Values (float32, nudged, ties settled) at `pts`, split after the first `k`, and the
            evaluations spent."""
            if not pts.shape[0]:
                return _NO_VALUES, _NO_VALUES, 0
            vals = _evaluate(self.solid, pts)
            # (one compiled pass when no value is a tie, the usual case)
            out, clean = nudged_float32(vals, ZERO_NUDGE * h, ZERO_TIE * h)
            probes = 0
            if not clean:
                probes = _settle_ties(self.solid, pts, vals, h)
                # (no tie is left: the same compiled pass)
                out, clean = nudged_float32(vals, ZERO_NUDGE * h, ZERO_TIE * h)
                if not clean:
                    out = _nudge(vals, h).astype(np.float32)
            return out[:k], out[k:], int(pts.shape[0]) + probes

        # -- pass 1: nodes of unknown sign ---------------------------------------------------
        rows, ru, pts = first_pass(flat, maybe, s_n, m_idx, ufirst, s_u, B, int(x0), y_base, z_base, origin, h)
        a, b, n = sample(pts, rows.shape[0])
        spent += n
        # -- pass 2: the ends of crossing edges without a value -------------------------------
        # (before marching cubes, which resolves its ambiguous faces and cubes from the values)
        # (the codes are spent: their memory holds the signs)
        rows, ru, pts = second_pass(a, b, rows, ru, flat, maybe, s_n, v_n, m_idx, ufirst, back, s_u, v_u,
                                    code.reshape(-1).view(np.int8), B, int(x0), y_base, z_base, origin, h,
                                    _take(self.scratch, "ends", (n_need,), np.bool_))
        del code, a, b
        a, b, n = sample(pts, rows.shape[0])
        spent += n
        del pts
        # -- marching cubes: a sign-only node gets +-L h, an unused node 1 ------------------
        # (the upper plane goes to the next slab: values NaN where only the sign is known)
        scale = np.float32(self.lip * h if self.lip else h)
        values = _take(self.scratch, "values", (self.nb * (B + 1) ** 3,), np.float32)
        hid, hval, hsgn = slab_samples(a, b, rows, ru, flat, v_n, s_n, m_idx, back, v_u, values, scale, upper, B,
                                       int(x0), y_base, z_base, int(stride))
        values = values.reshape(self.nb, B + 1, B + 1, B + 1)
        # every block's box (its cells' bounds), and which boxes hold a tie of marching cubes: found here,
        # so that the meshing thread runs the tie finder only on those
        self.lows, self.highs = block_boxes(*self.cl, self.nb, self.P)
        self.ties = blocks_with_ties(values, self.lows, self.highs, c)
        return cells, values, spent, (self.slab, hid, hval, hsgn)

    def run(self, sc, given, ring, centre_infer, handoff, parts, extra=None):
        """Sample and mesh; returns ``(blocks meshed, evaluations, handoff)``."""
        cells, values, spent, handoff = self.prepare(sc, given, ring, centre_infer, handoff, extra)
        self.mesh(cells, values, parts)
        return self.nb, spent, handoff

    def mesh(self, cells, values, parts):
        """Marching cubes of the prepared slab (`prepare`), its part appended to `parts`; returns the
        number of vertices made."""
        raw = self._mesh_blocks(cells, values)
        if raw is None:
            return 0
        parts.append(raw)
        return raw[1].shape[0]

    def _mesh_blocks(self, cells, values):
        """Marching cubes on every active block of the slab: the slab's part for `merge_blocks`
        (global edge ids of the vertices in block faces, their mask, ``(node, axis, f0, f1)``,
        faces), or None."""
        B, c, x0, stride = self.B, self.c, self.x0, self.stride
        lows, highs, ties = self.lows, self.highs, self.ties.tolist()
        scratch = self.scratch if self.scratch is not None else _Scratch()
        buf = scratch.buffers(self.capacity_hint)
        # one block's mask at a time, built in place (no slab of voxels, no per-block arrays)
        flat_mask = _take(scratch, "mask", ((B + 1) ** 3,), np.bool_)
        # the marks of `break_ties_marked`: cleared once, left clear by every block
        flat_marks = scratch.marks((B + 1) ** 3)
        # every block's box corner and size (voxels) and global corner as Python ints, in one go
        boxes = np.concatenate([lows * c, (highs - lows) * c, (self.bys * B)[:, None], (self.bzs * B)[:, None]],
                               axis=1).tolist()
        stride = int(stride)
        for b in range(self.nb):
            xs, ys, zs, nx, ny, nz, gy, gz = boxes[b]
            shape = (nx + 1, ny + 1, nz + 1)
            size = shape[0] * shape[1] * shape[2]
            # the box as a view of the slab's samples: scikit-image's kernel reads strided boxes as it
            # reads contiguous ones (the same output), so no box is copied
            vol = values[b, xs:xs + nx + 1, ys:ys + ny + 1, zs:zs + nz + 1]
            block_mask_held(values, cells, b, xs, ys, zs, nx, ny, nz, c, flat_mask)
            if ties[b]:
                # contacts fuse (saddles.py): the tie corners deepened in a copy
                vol = break_ties_marked(vol, flat_marks[:size].reshape(shape))
            verts, tri = _marching_cubes_raw(vol, flat_mask[:size].reshape(shape))
            if verts.shape[0] == 0 or tri.shape[0] == 0:
                continue
            buf.reserve(verts.shape[0], tri.shape[0] // 3)
            buf.vat, buf.fat, buf.eat = take_block_held(
                verts, tri, values, b, xs, ys, zs, B, x0, gy, gz, stride, buf.node, buf.axis,
                buf.f0, buf.f1, buf.shared, buf.edge, buf.faces, buf.vat, buf.fat, buf.eat)
        if buf.vat == 0:
            return None
        return buf.part()


class _Scratch:
    """Slab-sized arrays lent from one slab to the next of a `run_slabs` call: the dense node codes
    and samples, one block's mask, the vertex buffers.  Every use writes all it reads
    (`ring_to_nodes`, `fill_values`, `block_input`), so nothing of an earlier slab shows through;
    reuse saves the page faults of fresh arrays (some 300 MB of them per N=512 mesh)."""

    def __init__(self):
        self.arrays = {}
        self._buffers = None
        self._marks = None

    def take(self, name, shape, dtype):
        n = int(np.prod(shape))
        arr = self.arrays.get(name)
        # grown with room to spare; given back when the slabs get much smaller (the last slabs are
        # meshed when the parts are largest: no spare memory then)
        if arr is None or arr.dtype != dtype or not n <= arr.shape[0] <= 2 * n + 4096:
            self.arrays[name] = None
            arr = np.empty(n + n // 4, dtype=dtype)
            self.arrays[name] = arr
        return arr[:n].reshape(shape)

    def marks(self, n):
        """``n`` False booleans, kept for the next slab (their users leave them False)."""
        if self._marks is None or self._marks.shape[0] < n:
            self._marks = np.zeros(n, dtype=np.bool_)
        return self._marks[:n]

    def buffers(self, capacity):
        if self._buffers is None or self._buffers.cap > 2 * capacity + 4096:
            self._buffers = None
            self._buffers = _SlabBuffers(capacity)
        else:
            self._buffers.vat = self._buffers.fat = self._buffers.eat = 0
        return self._buffers


def _take(scratch, name, shape, dtype):
    """``np.empty(shape, dtype)``, from `scratch` when there is one."""
    if scratch is None:
        return np.empty(shape, dtype=dtype)
    return scratch.take(name, shape, dtype)


class _SlabBuffers:
    """Growing per-slab arrays the blocks' vertices and faces are written into (no list of pieces
    to concatenate); `part` trims them to the part `merge_blocks` takes."""

    def __init__(self, capacity):
        self.vat = self.fat = self.eat = 0
        self._alloc(max(int(capacity), 1024))

    def _alloc(self, cap, old=None):
        self.cap = cap
        self.node = np.empty((cap, 3), np.int32)
        self.axis = np.empty(cap, np.uint8)
        self.f0 = np.empty(cap, np.float32)
        self.f1 = np.empty(cap, np.float32)
        self.shared = np.empty(cap, np.bool_)
        self.edge = np.empty(cap, np.int64)
        self.faces = np.empty((2 * cap + 16, 3), np.int32)
        if old is not None:
            for name in ("node", "axis", "f0", "f1", "shared"):
                getattr(self, name)[:self.vat] = getattr(old, name)[:self.vat]
            self.edge[:self.eat] = old.edge[:self.eat]
            self.faces[:self.fat] = old.faces[:self.fat]

    def reserve(self, nv, nf):
        if self.vat + nv > self.cap or self.fat + nf > self.faces.shape[0]:
            old = _Old(self)
            self._alloc(max(2 * self.cap, self.vat + nv, (self.fat + nf) // 2 + 1), old)

    def part(self):
        v, f, e = self.vat, self.fat, self.eat

        def trim(arr, n):
            return arr[:n].copy()  # the buffers' spare room is not kept alive by the part

        return (trim(self.edge, e), trim(self.shared, v),
                (trim(self.node, v), trim(self.axis, v), trim(self.f0, v), trim(self.f1, v)), trim(self.faces, f))


class _Old:
    def __init__(self, buf):
        self.__dict__.update(buf.__dict__)


def _marching_cubes_raw(values, mask):
    """scikit-image's Lewiner marching cubes at level 0 from its Cython kernel: vertices (columns in
    reversed axis order) and flat triangles (wound for ``ascent``).  The Python wrapper's checks,
    flips and copies are left out: `take_block` reads the kernel's output as it is."""
    global _LUTS, _MC
    if _MC is None:
        from skimage.measure import _marching_cubes_lewiner_cy as cy
        from skimage.measure._marching_cubes_lewiner import _get_mc_luts

        _LUTS, _MC = _get_mc_luts(), cy.marching_cubes
    verts, tri, _, _ = _MC(values, 0.0, _LUTS, 1, False, mask)
    return verts, tri


_LUTS = _MC = None


def run_slabs(tasks, parts, overlap=False):
    """Prepare and mesh slabs in order; yields ``(blocks meshed, evaluations)`` per slab.

    `tasks` yields ``(job, (cells, given, ring, centre_infer, extra))``; each slab's preparation
    takes the previous one's handoff.  With `overlap`, a worker thread prepares slab ``k + 1``
    (compiled, GIL-free evaluation and bookkeeping for the most part) while this thread runs
    scikit-image's marching cubes on slab ``k`` (which holds the GIL): the two cores share the
    work.  At most two slabs are in flight, so memory grows by one slab's arrays.  The parts
    and counts are the same either way.
    """
    if not overlap:
        handoff = None
        made = 0
        scratch = _Scratch()
        for job, (sc, given, ring, centre_infer, extra) in tasks:
            job.scratch = scratch
            cells, values, spent, handoff = job.prepare(sc, given, ring, centre_infer, handoff, extra)
            # neighbouring slabs make about as many vertices: buffers sized from the last one
            job.capacity_hint = max(job.capacity_hint, made + made // 4)
            made = job.mesh(cells, values, parts)
            del cells, values
            # (the slab's temporaries stay in the heap for the next slab: handed back to the system
            # and faulted in again, slab after slab, they cost more system time than the slab's own
            # work -- 2.3 s of 11 s CPU at N=1024 -- for 2 % of the peak)
            yield job.nb, spent
        return
    ready = queue.Queue()
    stop = threading.Event()
    # at most two slabs in flight: the one being meshed here and the one being prepared; a slot is
    # given back when a slab is meshed (so two sets of slab arrays, not three)
    slots = threading.Semaphore(2)

    def wait_slot():
        while not stop.is_set():
            if slots.acquire(timeout=0.1):
                return True
        return False

    def work():
        try:
            handoff = None
            pool = [_Scratch() for _ in range(2)]
            for k, (job, (sc, given, ring, centre_infer, extra)) in enumerate(tasks):
                if not wait_slot():
                    return
                job.scratch = pool[k % 2]
                cells, values, spent, handoff = job.prepare(sc, given, ring, centre_infer, handoff, extra)
                ready.put((job, cells, values, spent))
                del cells, values
            ready.put(None)
        except BaseException as exc:  # handed to the meshing thread, raised there
            ready.put(exc)

    worker = threading.Thread(target=work, name="implicad-slab-prepare", daemon=True)
    # frequent hand-overs of the GIL: the worker's Python steps between its compiled calls should
    # not wait out the default 5 ms while marching cubes runs block after block
    _short_switches(True)
    worker.start()
    made = 0
    try:
        while True:
            item = ready.get()
            if item is None:
                break
            if isinstance(item, BaseException):
                raise item
            job, cells, values, spent = item
            del item
            job.capacity_hint = max(job.capacity_hint, made + made // 4)
            made = job.mesh(cells, values, parts)
            del cells, values
            slots.release()
            yield job.nb, spent
    finally:
        stop.set()
        worker.join()
        _short_switches(False)


_SWITCH_LOCK = threading.Lock()
_SWITCH_STATE = [0, None]  # meshes overlapping now, the interval before the first of them


def _short_switches(enter):
    """Shorten the interpreter's GIL switch interval while any overlapped mesh runs (meshes may run
    in several threads at once: the first one in saves the interval, the last one out restores it)."""
    with _SWITCH_LOCK:
        if enter:
            if _SWITCH_STATE[0] == 0:
                _SWITCH_STATE[1] = sys.getswitchinterval()
                sys.setswitchinterval(min(_SWITCH_STATE[1], SWITCH_INTERVAL))
            _SWITCH_STATE[0] += 1
        else:
            _SWITCH_STATE[0] -= 1
            if _SWITCH_STATE[0] == 0:
                sys.setswitchinterval(_SWITCH_STATE[1])


#: GIL switch interval (s) while slabs are prepared beside marching cubes.
SWITCH_INTERVAL = 5e-4
