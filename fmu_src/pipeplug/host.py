"""Where the core runs: set once by an adapter before any model is built.

``INSIDE_FMU`` is set by the FMU's slave. Inside an FMU the elastic kernels run as plain
Python unless the host opts in with the environment variable ``PIPEPLUG_JIT=1``: with
pythonfmu 0.7, a process that loaded numba (LLVM) inside an FMU unpacked to a temporary
folder can abort at exit, after the simulation, when pythonfmu's finaliser reads freed
memory. Hosts that unpack the FMU once to a fixed folder have not shown it.
"""
INSIDE_FMU = False
FMU_JIT_ENV = "PIPEPLUG_JIT"
