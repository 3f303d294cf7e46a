"""Run a checked system with libcosim (libcosimpy): every input and output of every component
after each communication step.

The execution comes from the file itself (``CosimExecution.from_ssp_file`` or
``from_osp_config_file``), so the step size, the parameter values and the connections are the
ones libcosim reads there. libcosim runs the FMUs in this process: call this only after
:func:`pipeplug_harness.system.checks.check_system` (a failed initialization would end the
process).
"""
from __future__ import annotations

import numpy as np

from .checks import Plan
from .files import SystemFile

__all__ = ["run_system"]

_NS = 1_000_000_000          # libcosim counts time in integer nanoseconds


def run_system(system: SystemFile, plan: Plan) -> dict:
    """Run ``system`` for ``plan.steps`` steps.

    Returns
    -------
    dict
        ``"time"`` [s] (libcosim's time after each step) and one array per input and output,
        keyed ``"<component>.<variable>"`` (Real as float, Integer as int, Boolean as bool). An
        input's value at a time is the one it had during the step that ended there.
    """
    from libcosimpy.CosimEnums import CosimVariableCausality, CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)
    path = str(system.path)
    execution = (CosimExecution.from_ssp_file(path) if system.route == "ssp"
                 else CosimExecution.from_osp_config_file(path))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    readers = {CosimVariableType.REAL.value: observer.last_real_values,
               CosimVariableType.INTEGER.value: observer.last_integer_values,
               CosimVariableType.BOOLEAN.value: observer.last_boolean_values}
    plans = []                       # (slave index, reader, [(column, value reference)])
    for name in system.components:
        index = execution.slave_index_from_instance_name(name)
        outputs = [v for v in execution.slave_variables(index) if v.type in readers
                   and v.causality in (CosimVariableCausality.INPUT.value,
                                       CosimVariableCausality.OUTPUT.value)]
        for kind, read in readers.items():
            chosen = [(f"{name}.{v.name.decode()}", v.reference) for v in outputs
                      if v.type == kind]
            if chosen:
                plans.append((index, read, chosen))
    columns = {"time": []} | {column: [] for _, _, chosen in plans for column, _ in chosen}
    for _ in range(plan.steps):
        if not execution.step():
            raise RuntimeError(f"libcosim failed a step after t = "
                               f"{execution.status().current_time / _NS!r} s")
        columns["time"].append(execution.status().current_time / _NS)
        for index, read, chosen in plans:
            for (column, _), value in zip(chosen, read(index, [vr for _, vr in chosen])):
                columns[column].append(value)
    del execution
    return {name: np.asarray(values) for name, values in columns.items()}
