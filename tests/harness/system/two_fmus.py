"""A fixed-step co-simulation of Hammer.fmu and PipePlug.fmu driven through FMPy's raw FMI 2.0
API, in a fresh process (both FMUs share its one interpreter):

    python two_fmus.py PIPEPLUG.fmu HAMMER.fmu '{"pipeplug": {...}, "hammer": {...},
                                                 "step": h, "stop": T}'

Both are initialized with their values; Hammer's Q after initialization goes to PipePlug's input
before the first step; then for each t_k = k h: doStep(t_k, h) on both, Hammer's Q (the force
for the next step) to PipePlug's input, PipePlug's outputs recorded. The last stdout line is
``RESULT <json>``: time and the outputs after each step.
"""
from __future__ import annotations

import json
import shutil
import sys
import tempfile

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
           "W_friction", "W_friction_outer", "W_friction_inner")


class Instance:
    def __init__(self, fmu: str, name: str, folder: str):
        unzipped = extract(fmu, folder)
        md = read_model_description(unzipped)
        self.vars = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate()

    def start(self, values: dict, stop: float) -> None:
        self.fmu.setupExperiment(startTime=0.0, stopTime=stop)
        self.fmu.enterInitializationMode()
        for name, value in values.items():
            v = self.vars[name]
            value = value.encode() if v.type == "String" else value
            getattr(self.fmu, "set" + v.type)([v.valueReference], [value])
        self.fmu.exitInitializationMode()

    def reals(self, names) -> list:
        return list(self.fmu.getReal([self.vars[n].valueReference for n in names]))


def main() -> None:
    pipeplug_fmu, hammer_fmu, spec = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
    h, stop = spec["step"], spec["stop"]
    folder = tempfile.mkdtemp()
    pipeplug = Instance(pipeplug_fmu, "PipePlug", folder + "/p")
    hammer = Instance(hammer_fmu, "Hammer", folder + "/h")
    pipeplug.start(spec["pipeplug"], stop)
    hammer.start(spec["hammer"], stop)
    q_in = pipeplug.vars["Q"].valueReference
    q = hammer.reals(["Q"])[0]                          # the force of the first step
    rows = {"time": [], "Q_applied": [], **{name: [] for name in OUTPUTS}}
    n = round(stop / h)
    for k in range(n):
        t = k * h
        pipeplug.fmu.setReal([q_in], [q])
        pipeplug.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        hammer.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        rows["time"].append((k + 1) * h)
        rows["Q_applied"].append(q)
        for name, value in zip(OUTPUTS, pipeplug.reals(OUTPUTS)):
            rows[name].append(value)
        q = hammer.reals(["Q"])[0]
    for instance in (pipeplug, hammer):
        instance.fmu.terminate()
        instance.fmu.freeInstance()
    shutil.rmtree(folder, ignore_errors=True)
    sys.stdout.write("\nRESULT " + json.dumps(rows) + "\n")


if __name__ == "__main__":
    main()
