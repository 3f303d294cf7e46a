"""pipeplug_harness: the ``pipeplug`` command (fmpy) and its jobs, one subpackage per job.

``validate``, ``figures``, ``cost``, ``hardcases`` (the ``stability`` command), ``scenes``,
``drive`` (a whole drive, blow by blow, through one FMU instance), ``system`` (Hammer and
PipePlug co-simulated in libcosim), ``fuzz`` (differential fuzzing of the rigid models) and
:mod:`pipeplug_harness.session` drives the FMU and the core; the shared layer is
drives the FMU as users do. The references it checks against live in
:mod:`pipeplug_references`, which never imports the core.
"""
