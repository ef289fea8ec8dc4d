"""Cached kernels load without numba's target refresh (`implicit.evaluate.numba_start`).

A throw-away module of cached kernels (one allocating an array, one parallel) is compiled
in a first fresh interpreter, then loaded in a second: the second gives the same values,
never imports numba's linalg registry (the refresh's mark), and still compiles a new
kernel that needs it, and one that calls a loaded kernel (linking the bitcode the load left unparsed);
the environments of numba's own modules that the loaded kernels inlined are rebuilt without importing them,
and numba's runtime functions are compiled by the first process only.
The names a cached object defines, read from its ELF symbol table, are those numba reads from
its bitcode.
"""

import json
import os
import subprocess
import sys
import textwrap

import pytest

pytest.importorskip("numba")

KERNELS = textwrap.dedent('''
    import numba
    import numpy as np

    @numba.njit(cache=True)
    def cumulative(x):
        out = np.empty(x.size)        # an allocation: needs numba's runtime
        total = 0.0
        for i in range(x.size):
            total += x[i] * x[i]
            out[i] = total
        return out

    @numba.njit(cache=True, parallel=True)
    def doubled(x):
        out = np.empty_like(x)
        for i in numba.prange(x.size):
            out[i] = 2.0 * x[i]
        return out
''')

JOB = textwrap.dedent('''
    import json, sys
    import implicit  # installs the start-up
    import numpy as np
    import numba
    import numba.core.runtime.nrtdynmod as nrtdynmod
    made, create = [], nrtdynmod.create_nrt_module
    nrtdynmod.create_nrt_module = lambda ctx: made.append(1) or create(ctx)   # the runtime compiled from IR
    import kernels
    import numba.core.caching as caching
    from numba.core import event
    heard = event.RecordingListener()
    event.register("numba:llvm_lock", heard)
    inner, during = caching.Cache._load_overload, []
    def counted(self, *args):     # the LLVM lock events heard while one cached kernel loads
        before = len(heard.buffer)
        result = inner(self, *args)
        during.append(len(heard.buffer) - before)
        return result
    caching.Cache._load_overload = counted
    x = np.arange(1.0, 6.0)
    a = kernels.cumulative(x).tolist()
    b = kernels.doubled(x).tolist()
    lock_events = during
    refreshed = "numba.np.linalg" in sys.modules
    arrayobj = "numba.np.arrayobj" in sys.modules  # np.empty's module, whose environment the loads rebuilt
    @numba.njit
    def norm(v):
        return np.linalg.norm(v)       # typing this needs the registries the load skipped
    @numba.njit
    def last(v):
        return kernels.cumulative(v)[-1]   # links the loaded kernel: its bitcode is parsed now
    @numba.njit
    def fresh(v):
        out = np.empty(v.size)             # lowers np.empty after the loads rebuilt its environment
        out[:] = v
        return out.sum()
    print(json.dumps(dict(a=a, b=b, refreshed=refreshed, norm=norm(x), last=last(x), lock_events=lock_events,
                          arrayobj=arrayobj, fresh=fresh(x), runtime_compiled=len(made))))
''')


def _run(tmp_path, **env):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(tmp_path), **env)
    proc = subprocess.run([sys.executable, "-c", JOB], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_cached_kernels_load_without_the_refresh_and_compile_after(tmp_path):
    (tmp_path / "kernels.py").write_text(KERNELS)
    first = _run(tmp_path)
    assert first["refreshed"]  # compiling refreshes, as numba does
    second = _run(tmp_path)
    assert second["a"] == [1.0, 5.0, 14.0, 30.0, 55.0]
    assert second["b"] == [2.0, 4.0, 6.0, 8.0, 10.0]
    assert not second["refreshed"]
    assert not second["arrayobj"]  # the loads imported none of numba's implementation modules
    # the kernels cached with the start-up installed name numba's own rebuild, not the start-up's
    cached = list((tmp_path / "cache").rglob("*.nbc"))
    assert cached and not any(b"numba_start" in p.read_bytes() for p in cached)
    assert first["fresh"] == second["fresh"] == 15.0
    # the runtime's functions: compiled and written by the first process, loaded by the second
    assert first["runtime_compiled"] == 1 and second["runtime_compiled"] == 0
    (saved,) = (tmp_path / "cache").glob("numba_runtime-*.nbo")
    saved.write_bytes(b"damaged")
    third = _run(tmp_path)  # a damaged file is compiled again, and rewritten
    assert third["runtime_compiled"] == 1 and third["a"] == second["a"] and third["fresh"] == 15.0
    assert _run(tmp_path)["runtime_compiled"] == 0
    assert second["norm"] == pytest.approx(55.0 ** 0.5, rel=1e-15)
    assert first["last"] == second["last"] == 55.0
    assert len(second["lock_events"]) == 2 and sum(second["lock_events"]) == 0  # loads broadcast no lock events
    # numba's own start-up on request: the same values, with the refresh
    full = _run(tmp_path, IMPLICAD_NUMBA_FULL_START="1")
    assert full["refreshed"] and full["arrayobj"] and full["a"] == second["a"] and full["b"] == second["b"]
    assert full["last"] == 55.0 and len(full["lock_events"]) == 2 and min(full["lock_events"]) > 0
    assert full["runtime_compiled"] == 1


def test_install_is_idempotent_and_marks_the_loader():
    import numba.core.caching as caching

    from implicit.evaluate import numba_start

    numba_start.install()
    numba_start.install()
    if os.environ.get(numba_start.FULL_START) != "1":
        assert numba_start.installed()
        assert caching.Cache.load_overload.__wrapped__ is not None
        assert not hasattr(caching.Cache.load_overload.__wrapped__, "__wrapped__")  # wrapped once


def test_object_symbols_are_the_bitcode_s_defined_globals():
    # every kernel the evaluator caches: the machine code's global symbols against the names
    # numba's own loader would take from the bitcode (external or weak definitions)
    import glob
    import pickle

    import llvmlite.binding as ll

    from implicit.evaluate import kernels
    from implicit.evaluate.numba_objects import defined_symbols

    kernels.prime_cache()
    folder = os.path.join(os.path.dirname(kernels.__file__), "__pycache__")
    files = sorted(glob.glob(os.path.join(folder, "jit.*.nbc")))
    assert files, "no cached kernel to read"

    def library_state(obj, depth=0):
        if isinstance(obj, tuple) and len(obj) == 3 and obj[1] == "object":
            return obj
        if isinstance(obj, (tuple, list)) and depth < 6:
            for item in obj:
                found = library_state(item, depth + 1)
                if found is not None:
                    return found
        return None

    checked = 0
    for path in files:
        with open(path, "rb") as handle:
            state = library_state(pickle.loads(handle.read()))
        if state is None:
            continue
        code, bitcode = state[2]
        module = ll.parse_bitcode(bitcode)
        exported = {g.name for group in (module.functions, module.global_variables) for g in group
                    if not g.is_declaration and g.linkage not in (ll.Linkage.internal, ll.Linkage.private)}
        names = defined_symbols(code)
        assert names == exported, path
        assert any(n.startswith("_ZN7cpython") for n in names), path  # the wrapper numba asks for
        checked += 1
    assert checked >= 4


def test_object_symbols_refuse_what_is_not_an_elf_object():
    from implicit.evaluate.numba_objects import defined_symbols

    assert defined_symbols(b"\x7fELF" + bytes(60)) is None       # 32-bit class byte: not read
    assert defined_symbols(b"\xcf\xfa\xed\xfe" + bytes(60)) is None  # Mach-O
    with pytest.raises(TypeError, match="obj: expected the bytes of an object file"):
        defined_symbols("cpython.f")


EXTENSION_JOB = textwrap.dedent('''
    import json, sys
    import importlib.metadata as md
    import implicit  # installs the start-up
    import numba
    import numpy as np
    calls = []
    scan = md.entry_points
    md.entry_points = lambda *a, **k: calls.append(1) or scan(*a, **k)
    @numba.njit
    def twice(x):
        return 2.0 * x
    twice(1.0)
    import fake_extension
    print(json.dumps(dict(scanned=len(calls), loaded=fake_extension.LOADED)))
''')


@pytest.mark.parametrize("declared", [False, True])
def test_numba_extensions_are_looked_for_only_where_one_is_declared(tmp_path, declared):
    (tmp_path / "fake_extension.py").write_text("LOADED = []\ndef init():\n    LOADED.append(1)\n")
    info = tmp_path / "fake_extension-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-extension\nVersion: 1.0\n")
    group = "numba_extensions" if declared else "console_scripts"
    (info / "entry_points.txt").write_text(f"[{group}]\ninit = fake_extension:init\n")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    env.pop("IMPLICAD_NUMBA_FULL_START", None)
    proc = subprocess.run([sys.executable, "-c", EXTENSION_JOB], env=env, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    # declared: numba reads the entry points and runs the extension's init, as without the start-up
    assert got == (dict(scanned=1, loaded=[1]) if declared else dict(scanned=0, loaded=[]))


def test_no_numba_extensions_reads_the_entry_points_files(tmp_path, monkeypatch):
    from implicit.evaluate.numba_start import no_numba_extensions

    class Finder:  # another source of distributions: numba must look for itself
        def find_spec(self, *args):
            return None

        def find_distributions(self, *args):
            return iter(())

    monkeypatch.setattr(sys, "path", [str(tmp_path)])
    monkeypatch.setattr(sys, "meta_path", [m for m in sys.meta_path if not hasattr(m, "find_distributions")
                                           or getattr(m, "__name__", "") == "PathFinder"])
    assert no_numba_extensions()
    monkeypatch.setattr(sys, "meta_path", [Finder()] + sys.meta_path)
    assert not no_numba_extensions()

    assert no_numba_extensions([str(tmp_path), str(tmp_path / "missing")])
    (tmp_path / "plain.egg-info").write_text("Name: plain\n")  # an egg-info file, no entry points
    assert no_numba_extensions([str(tmp_path)])
    info = tmp_path / "ext-1.0.dist-info"
    info.mkdir()
    (info / "entry_points.txt").write_text("[numba_extensions]\ninit = ext:init\n")
    assert not no_numba_extensions([str(tmp_path)])
    zipped = tmp_path / "bundle.zip"
    zipped.write_bytes(b"PK")
    assert not no_numba_extensions([str(zipped)])  # not read: numba looks for itself
