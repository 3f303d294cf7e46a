"""pipeplug_harness: the ``pipeplug`` command (fmpy) and its jobs, one subpackage per job.

``validate``, ``figures``, ``cost``, ``stability`` (the hard cases), ``scene``, ``drive`` (a
whole drive, blow by blow, through one FMU instance), ``system`` (Hammer and PipePlug
co-simulated in libcosim), ``fuzz`` (differential fuzzing of the rigid and elastic models) and
``sweep`` (campaigns on Dask). They share one layer: :mod:`~pipeplug_harness.spec` (the file
format), :mod:`~pipeplug_harness.load` (loads), :mod:`~pipeplug_harness.session` (the one way
to drive the FMU or the core, as users do), :mod:`~pipeplug_harness.io` (files),
:mod:`~pipeplug_harness.paper` (the paper's constants and names), :mod:`~pipeplug_harness.errors`
and :mod:`~pipeplug_harness.limits`. The references it checks against live in
:mod:`pipeplug_references`, which never imports the core.
"""
