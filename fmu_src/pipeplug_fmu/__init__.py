"""pipeplug_fmu: the FMI adapters of PipePlug and Hammer, the build of their FMUs and of the
pipe-ramming system files.

* :mod:`pipeplug_fmu.slave`: the pythonfmu slave around the core (runs only inside an FMU);
* :mod:`pipeplug_fmu.fmi`: the FMUs' interface tables, refusals and modelDescription additions;
* :mod:`pipeplug_fmu.blows`: Hammer's blow train (its parameter table, checks and force);
* :mod:`pipeplug_fmu.hammer`: Hammer's pythonfmu slave (runs only inside an FMU);
* :mod:`pipeplug_fmu.native`: the FMUs' linux64 binary, a C loader in front of pythonfmu's
  (finds a Python, log categories, fmi2Error for refusals, resource URIs, exit guard);
* :mod:`pipeplug_fmu.documentation`, :mod:`pipeplug_fmu.hammer_documentation`: the FMUs'
  ``documentation/index.html``;
* :mod:`pipeplug_fmu.systems`: ``PipeRamming.ssp`` and ``OspSystemStructure.xml``, Hammer
  driving PipePlug;
* :mod:`pipeplug_fmu.build`: ``python -m pipeplug_fmu build`` writes ``dist/PipePlug.fmu``,
  ``dist/Hammer.fmu`` and the system files.

Importing this package imports nothing else: it is shipped inside the FMUs as it is.
"""
