"""libcosim scenarios (libcosimpy), run in a fresh process by ``fmu_scenarios.py``.

libcosim loads the FMU in the same process (pythonfmu shares the interpreter), so a crash of
the FMU would be a crash of this process: the test sees no result. Start values are checked with
:func:`pipeplug_harness.cosim.check_parameters` before an execution is built.
"""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
           "W_friction")

_OSP = """<?xml version="1.0" encoding="utf-8"?>
<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure"
                    version="0.1">
  <StartTime>0.0</StartTime>
  <BaseStepSize>{step}</BaseStepSize>
  <Algorithm>fixedStep</Algorithm>
  <Simulators>
    <Simulator name="pipeplug" source="PipePlug.fmu" stepSize="{step}">
      <InitialValues>
{initial}
      </InitialValues>
    </Simulator>
  </Simulators>
</OspSystemStructure>
"""


def _initial_value(name, value) -> str:
    kind = "String" if isinstance(value, str) else "Real"
    return f'        <InitialValue variable="{name}"><{kind} value="{value}"/></InitialValue>'


def _execution(fmu_file, params, step, tmp):
    """libcosim's execution of PipePlug with ``params``, checked by the core first (libcosim
    terminates the process when an FMU fails exitInitializationMode)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    from pipeplug_harness.cosim import check_parameters

    check_parameters(params)
    log_output_level(CosimLogLevel.WARNING)
    shutil.copy(fmu_file, Path(tmp) / "PipePlug.fmu")
    initial = "\n".join(_initial_value(k, v) for k, v in params.items())
    osp = Path(tmp) / "OspSystemStructure.xml"
    osp.write_text(_OSP.format(step=repr(step), initial=initial))
    return CosimExecution.from_osp_config_file(str(osp))


def _driven(fmu_file, params, step, tmp):
    """An execution with an override manipulator for Q and a last-value observer attached."""
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver

    execution = _execution(fmu_file, params, step, tmp)
    index = execution.slave_index_from_instance_name("pipeplug")
    vrs = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
    override = CosimManipulator.create_override()
    observer = CosimObserver.create_last_value()
    execution.add_manipulator(override)
    execution.add_observer(observer)
    return execution, index, vrs, override, observer


def cosim_pulse(fmu_file, params, q0, t0, step, checkpoints):
    """Run under the pulse (Q set by an override manipulator); outputs at the checkpoints [s]."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        execution, index, vrs, override, observer = _driven(fmu_file, params, step, tmp)
        for t in checkpoints:           # the pulse edge t0 must be one of the checkpoints
            override.slave_real_values(index, [vrs["Q"]], [q0 if t <= t0 else 0.0])
            if not execution.simulate_until(round(t * 1e9)):
                raise RuntimeError(f"libcosim stopped before {t} s")
            rows.append(dict(zip(OUTPUTS, observer.last_real_values(
                index, [vrs[name] for name in OUTPUTS]))))
        del execution
    return {"rows": rows}


def cosim_refused_parameters(fmu_file, params):
    """An execution with invalid ``params``: refused before libcosim sees it (the message)."""
    from pipeplug import ParameterError

    with tempfile.TemporaryDirectory() as tmp:
        try:
            _execution(fmu_file, params, 1e-3, tmp)
        except ParameterError as exc:
            return {"refused": str(exc)}
    return {"refused": None}


def cosim_refused_step(fmu_file, params, q0, step, t_nan):
    """Q = q0 until ``t_nan`` [s], then NaN: whether each run succeeded; v_pipe at the end."""
    with tempfile.TemporaryDirectory() as tmp:
        execution, index, vrs, override, observer = _driven(fmu_file, params, step, tmp)
        override.slave_real_values(index, [vrs["Q"]], [q0])
        ok_before = execution.simulate_until(round(t_nan * 1e9))
        override.slave_real_values(index, [vrs["Q"]], [float("nan")])
        ok_after = execution.simulate_until(round(2 * t_nan * 1e9))
        v_pipe = observer.last_real_values(index, [vrs["v_pipe"]])[0]
        del execution
    return {"ok_before": bool(ok_before), "ok_after": bool(ok_after), "v_pipe": v_pipe}
