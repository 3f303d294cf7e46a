"""pipeplug_fmu: the FMI adapters of PipePlug and Hammer, the build of their FMUs and of the
pipe-ramming system files.

* :mod:`pipeplug_fmu.base`: the FMI base of both slaves (call sequence, refusals, FMU state;
  with :mod:`pipeplug_fmu.sequence` and :mod:`pipeplug_fmu.fmu_state`);
* :mod:`pipeplug_fmu.fmi2`, :mod:`pipeplug_fmu.fmi3`: the FMI 2.0 (pythonfmu 0.7) and FMI 3.0
  (pythonfmu3) bindings of that base; :mod:`pipeplug_fmu.fmi2_pipeplug`,
  :mod:`pipeplug_fmu.fmi2_hammer`: the FMI 2.0 FMUs' classes (the FMI 3.0 ones are defined in
  their slave scripts, see :mod:`pipeplug_fmu.build`);
* :mod:`pipeplug_fmu.pythonfmu07`: every pythonfmu 0.7 workaround, with the behaviour it works
  around;
* :mod:`pipeplug_fmu.slave`: the slave around the core, for either binding (runs only inside an
  FMU);
* :mod:`pipeplug_fmu.fmi`: the FMUs' interface tables, refusal wording and modelDescription
  additions;
* :mod:`pipeplug_fmu.blows`: Hammer's blow train (its parameter table, checks and force);
* :mod:`pipeplug_fmu.hammer`: Hammer's slave, for either binding (runs only inside an FMU);
* :mod:`pipeplug_fmu.native`: the FMUs' linux64 binary, a C loader in front of pythonfmu's
  (finds a Python, log lines and statuses, the gate after an error, argument, resource and
  FMU-state checks, exit guard);
* :mod:`pipeplug_fmu.documentation`, :mod:`pipeplug_fmu.hammer_documentation`: the FMUs'
  ``documentation/index.html``;
* :mod:`pipeplug_fmu.systems`: ``PipeRamming.ssp`` and ``OspSystemStructure.xml``, Hammer
  driving PipePlug;
* :mod:`pipeplug_fmu.build`: ``python -m pipeplug_fmu build`` writes ``dist/PipePlug.fmu``,
  ``dist/Hammer.fmu``, the system files and ``dist/fmi3/``.

Importing this package imports nothing else: it is shipped inside the FMUs as it is.
"""
