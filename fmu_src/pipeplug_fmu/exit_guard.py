"""Keep a Python host alive at exit despite pythonfmu 0.7's double release of its interpreter state.

The FMU binary that pythonfmu 0.7 ships keeps the interpreter state in a global
``std::shared_ptr`` (``(anonymous namespace)::pyState``). At process exit the C++ runtime first
destroys that global (releasing its control block), then the library's ELF destructor
``finalizePythonInterpreter`` resets the same pointer again: it decrements counters inside the
freed block. When that block already sits in one of malloc's bins this overwrites a free-list
pointer, and glibc aborts the host ("corrupted double-linked list") after the simulation has
ended, at random (more often when numba or other large libraries are loaded).

The guard registers a Python ``atexit`` hook. A Python host runs it during interpreter
finalisation, before the C++ exit handlers: it clears the 16 bytes of every mapped copy of the
binary's ``pyState`` so that both releases see an empty pointer. The state is then left to the
operating system, which reclaims it with the process. The symbol's offset is read from the
binary's ELF symbol table when the FMU is loaded (the file may be deleted by the time the
process exits). Linux x86-64/aarch64 only; anywhere else, or if anything does not look exactly
as expected, the guard does nothing.
"""
from __future__ import annotations

import atexit
import ctypes
import struct
import sys
from pathlib import Path

__all__ = ["install"]

_SYMBOL = b"_ZN12_GLOBAL__N_17pyStateE"      # (anonymous namespace)::pyState
_SIZE = 16                                   # a shared_ptr: object pointer, control block
_installed: dict[str, int] = {}              # binary file name -> symbol offset


def install(binary: Path) -> bool:
    """Arm the guard for the pythonfmu binary at ``binary`` (once per file name).

    Returns True when armed. Never raises: a guard that cannot be armed changes nothing.
    """
    try:
        if not sys.platform.startswith("linux") or binary.name in _installed:
            return binary.name in _installed
        offset = _symbol_offset(binary.read_bytes())
        if offset is None:
            return False
        if not _installed:
            atexit.register(_clear_all)
        _installed[binary.name] = offset
        return True
    except Exception:
        return False


def _symbol_offset(elf: bytes) -> int | None:
    """Virtual address of ``pyState`` in a little-endian ELF64 shared object, or None."""
    if elf[:4] != b"\x7fELF" or elf[4] != 2 or elf[5] != 1:
        return None
    (e_phoff, e_shoff) = struct.unpack_from("<QQ", elf, 0x20)
    (e_phentsize, e_phnum, e_shentsize, e_shnum) = struct.unpack_from("<HHHH", elf, 0x36)
    first_load = next((struct.unpack_from("<QQ", elf, e_phoff + i * e_phentsize + 8)
                       for i in range(e_phnum)
                       if struct.unpack_from("<I", elf, e_phoff + i * e_phentsize)[0] == 1),
                      None)
    if first_load is None or first_load != (0, 0):      # (p_offset, p_vaddr) of PT_LOAD[0]
        return None
    sections = [struct.unpack_from("<IIQQQQIIQQ", elf, e_shoff + i * e_shentsize)
                for i in range(e_shnum)]
    for sh in sections:
        if sh[1] != 2:                                   # SHT_SYMTAB
            continue
        names = sections[sh[6]]                          # sh_link: its string table
        for k in range(sh[5] // sh[9]):
            st_name, _, _, _, st_value, st_size = struct.unpack_from("<IBBHQQ", elf,
                                                                      sh[4] + k * sh[9])
            start = names[4] + st_name
            if elf[start:start + len(_SYMBOL) + 1] == _SYMBOL + b"\0" and st_size == _SIZE:
                return st_value
    return None


def _mapped_bases() -> dict[str, list[int]]:
    """Load addresses of the guarded binaries currently mapped, by file name."""
    bases: dict[str, list[int]] = {}
    with open("/proc/self/maps") as maps:
        for line in maps:
            fields = line.split(maxsplit=5)
            if len(fields) < 6 or int(fields[2], 16) != 0:
                continue
            path = fields[5].strip().removesuffix(" (deleted)")
            name = Path(path).name
            if name in _installed and "/binaries/" in path:
                bases.setdefault(name, []).append(int(fields[0].split("-")[0], 16))
    return bases


def _clear_all() -> None:
    """Empty every mapped ``pyState`` (run by ``atexit``, before the C++ exit handlers)."""
    try:
        for name, starts in _mapped_bases().items():
            for base in starts:
                ctypes.memset(base + _installed[name], 0, _SIZE)
    except Exception:
        pass
