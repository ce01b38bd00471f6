"""The engine: truth model, flight software, commands, scenarios, runner.

numba's on-disk cache notices when a compiled function's own file changes but
not when a function it calls (in another module) does, so a cached kernel can
silently run stale code. The cache therefore lives in a directory named after
a hash of every source file here: any edit starts a fresh cache.
"""
import hashlib
import os
from pathlib import Path


def _source_hash() -> str:
    h = hashlib.sha256()
    root = Path(__file__).parent
    for path in sorted(root.rglob("*.py")):
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _use_versioned_numba_cache() -> None:
    if "NUMBA_CACHE_DIR" in os.environ:
        return  # the user chose a place; respect it
    base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "acs-numba"
    cache_dir = str(base / _source_hash())
    os.environ["NUMBA_CACHE_DIR"] = cache_dir
    import numba  # reads the environment on first import; patch it if imported earlier

    numba.config.CACHE_DIR = cache_dir


_use_versioned_numba_cache()
