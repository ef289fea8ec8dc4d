"""Shared fixtures.

`requires_openvdb`: tests that need Debian's pyopenvdb take this fixture.  They
are skipped (with the reason) when the module is missing, EXCEPT when the
environment variable ``CI=true``: there a missing pyopenvdb fails the test.
"""

import os

import pytest


def _openvdb_or_reason():
    try:
        import pyopenvdb
    except ImportError as exc:
        return None, f"needs Debian's python3-openvdb (module pyopenvdb): {exc}"
    return pyopenvdb, ""


def require_openvdb():
    """The pyopenvdb module; skip without it, fail without it when CI=true."""
    module, reason = _openvdb_or_reason()
    if module is None:
        if os.environ.get("CI", "").strip().lower() == "true":
            pytest.fail(f"CI=true: {reason}")
        pytest.skip(reason)
    return module


@pytest.fixture
def requires_openvdb():
    """Fixture form of `require_openvdb`."""
    return require_openvdb()


@pytest.fixture
def fresh_cache_run(tmp_path):
    """Run a job in a fresh interpreter with its own numba cache folder, with cache debugging on.

    Returns a function ``run(job) -> str`` (the job's stdout and stderr); every call shares the
    folder, so a second call shows what the first one saved being loaded.
    """
    import subprocess
    import sys

    def run(job):
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DEBUG_CACHE="1")
        proc = subprocess.run([sys.executable, "-c", job], env=env, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-2000:]
        return proc.stdout + proc.stderr

    return run
