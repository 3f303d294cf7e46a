"""A refusal logged through FMPy's default logger, in a process of its own.

    python fmu_default_logger.py default_logger FMU_DIR '{"params": {"solver": "%s"}}'

FMPy's default logger printf-formats each message in C (a '%s' that is not escaped reads a
missing argument and crashes the host) and prints it. No other logger may be installed in the
process (FMPy's C proxy keeps the last one), so this does not import ``fmu_driver``.
"""
from __future__ import annotations

import json
import sys

from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave


def default_logger(fmu_dir, params):
    """exitInitializationMode with String ``params``; its status."""
    md = read_model_description(fmu_dir)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmu_dir, modelIdentifier="PipePlug",
                    instanceName="plain")
    fmu.instantiate(loggingOn=True)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for name, value in params.items():
        fmu.setString([vrs[name]], [value])
    try:
        fmu.exitInitializationMode()
        status = 0
    except FMICallException as exc:
        status = exc.status
    fmu.freeInstance()
    return {"status": status}


if __name__ == "__main__":
    result = default_logger(sys.argv[2], **json.loads(sys.argv[3]))
    sys.stdout.write("\nRESULT " + json.dumps(result) + "\n")
