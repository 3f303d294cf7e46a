"""The exit guard finds pythonfmu's interpreter state and hosts exit cleanly after FMU runs."""
import subprocess
import sys
import textwrap

PROBE = textwrap.dedent("""
    import ctypes, sys
    import numpy as np
    from fmpy import simulate_fmu
    signal = np.array([(0.0, 23e3), (0.05, 23e3), (0.05, 0.0), (0.06, 0.0)],
                      dtype=[("time", float), ("Q", float)])
    simulate_fmu(sys.argv[1], stop_time=0.06, output_interval=1e-3, input=signal,
                 start_values={"elastic": True, "dx": 0.05}, output=["v_pipe"])
    guard, = [m for name, m in sys.modules.items()
              if name.startswith("pipeplug_fmu_") and name.endswith(".exit_guard")]
    (name, offset), = guard._installed.items()
    (base,), = guard._mapped_bases().values()
    words = (ctypes.c_uint64 * 2).from_address(base + offset)
    # a live shared_ptr: two non-null, aligned heap addresses
    print("ARMED" if all(w and w % 8 == 0 for w in words) else "NOT A SHARED_PTR", name)
""")


def test_guard_is_armed_on_the_shared_ptr_and_hosts_exit_cleanly(fmu_file, tmp_path):
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    # Without the guard about half of such runs (numba loaded, FMU unpacked to a temporary
    # folder) aborted at exit with "corrupted double-linked list".
    for _ in range(6):
        proc = subprocess.run([sys.executable, str(script), str(fmu_file)], capture_output=True,
                              text=True, timeout=300, check=False)
        assert proc.returncode == 0, proc.stderr[-2000:]
        assert "ARMED PipePlug.so" in proc.stdout


def test_symbol_lookup_rejects_what_is_not_an_elf_shared_object(tmp_path):
    from pipeplug_fmu.exit_guard import _symbol_offset, install
    assert _symbol_offset(b"not an elf file" * 10) is None
    assert install(tmp_path / "missing.so") is False
