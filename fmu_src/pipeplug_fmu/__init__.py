"""pipeplug_fmu: the FMI adapter of PipePlug and the build of its FMU.

* :mod:`pipeplug_fmu.slave`: the pythonfmu slave around the core (runs only inside an FMU);
* :mod:`pipeplug_fmu.fmi`: the FMU's interface tables, refusals and modelDescription additions;
* :mod:`pipeplug_fmu.native`: the FMU's linux64 binary, a C loader in front of pythonfmu's
  (finds a Python, log categories, fmi2Error for refusals, resource URIs, exit guard);
* :mod:`pipeplug_fmu.documentation`: the FMU's ``documentation/index.html``;
* :mod:`pipeplug_fmu.build`: ``python -m pipeplug_fmu build`` writes ``dist/PipePlug.fmu``.

Importing this package imports nothing else: it is shipped inside the FMU as it is.
"""
