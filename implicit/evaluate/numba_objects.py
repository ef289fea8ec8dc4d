"""The symbols a cached kernel's object code defines, read from its ELF symbol table without LLVM.

numba caches a kernel as its machine code (an ELF object) and, beside it, the
LLVM bitcode of the same module, kept for linking the kernel into a later
compilation that calls it.  Loading a kernel, numba parses that bitcode and
walks every function and global of it through LLVM's C API (about 3 ms of a
10 ms load; 0.1 s over the 35 kernels of `implicad mesh`) for one thing: the
names the execution engine may be asked for without aborting the process
(`JitEngine._defined_symbols`).  The object code holds the same names in its
symbol table, a few kilobytes that numpy reads in microseconds; the bitcode
is parsed only if a later compilation links the kernel
(`implicit.evaluate.numba_start`).

Examples
--------
>>> defined_symbols(b"not an object") is None
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["defined_symbols"]

_SECTION = np.dtype([("name", "<u4"), ("type", "<u4"), ("flags", "<u8"), ("addr", "<u8"), ("offset", "<u8"),
                     ("size", "<u8"), ("link", "<u4"), ("info", "<u4"), ("addralign", "<u8"), ("entsize", "<u8")])
_SYMBOL = np.dtype([("name", "<u4"), ("info", "u1"), ("other", "u1"), ("shndx", "<u2"), ("value", "<u8"),
                    ("size", "<u8")])
_SHT_SYMTAB = 2
_STB_GLOBAL, _STB_WEAK = 1, 2


def defined_symbols(obj) -> frozenset | None:
    """Names of the global and weak symbols an ELF64 little-endian object defines; None for any other object.

    Local symbols (internal functions, sections, the file name) are left out:
    the execution engine cannot be asked for them by name.

    Parameters
    ----------
    obj : bytes
        A relocatable object file, as numba's cache stores a kernel's machine code.

    Returns
    -------
    frozenset of str, or None
        None when `obj` is not an ELF64 little-endian object with one symbol table
        (another platform's format): the caller then asks LLVM, as numba does.
    """
    if not isinstance(obj, (bytes, bytearray, memoryview)):
        raise TypeError(f"obj: expected the bytes of an object file, got {type(obj).__name__}")
    data = obj if isinstance(obj, bytes) else bytes(obj)
    if len(data) < 64 or data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        return None
    shoff = int.from_bytes(data[0x28:0x30], "little")
    shentsize = int.from_bytes(data[0x3A:0x3C], "little")
    shnum = int.from_bytes(data[0x3C:0x3E], "little")
    if shentsize != _SECTION.itemsize or shnum == 0 or shoff + shnum * shentsize > len(data):
        return None
    sections = np.frombuffer(data, _SECTION, count=shnum, offset=shoff)
    tables = np.flatnonzero(sections["type"] == _SHT_SYMTAB)
    if tables.size != 1:
        return None
    table = sections[tables[0]]
    if table["entsize"] != _SYMBOL.itemsize or table["link"] >= shnum:
        return None
    strings = sections[table["link"]]
    s0, s1 = int(strings["offset"]), int(strings["offset"] + strings["size"])
    t0, count = int(table["offset"]), int(table["size"]) // _SYMBOL.itemsize
    if s1 > len(data) or t0 + count * _SYMBOL.itemsize > len(data):
        return None
    symbols = np.frombuffer(data, _SYMBOL, count=count, offset=t0)
    bind = symbols["info"] >> 4
    keep = (symbols["shndx"] != 0) & ((bind == _STB_GLOBAL) | (bind == _STB_WEAK)) & (symbols["name"] != 0)
    table_bytes = data[s0:s1]
    # one name per defined global (tens per kernel), cut at its terminating NUL
    return frozenset(table_bytes[o:table_bytes.index(b"\0", o)].decode() for o in symbols["name"][keep].tolist())
