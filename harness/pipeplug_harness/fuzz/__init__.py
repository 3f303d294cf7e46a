"""pipeplug fuzz: differential fuzzing of the rigid models I and II.

Random cases (:mod:`.cases`: parameters in every domain, multi-segment loads of both signs and
loads exactly at a friction limit, coarse, fine and irregular communication grids) run
through every core path (:mod:`.paths`), and some of them through the independent reference
(:mod:`pipeplug_references.rigid_ivp`), one FMU instance and the paper's fd scheme
(:mod:`.runners`, :mod:`.fdcheck`). :func:`.run.run_case` turns one case into one result (a
pure function of the case); :mod:`.report` aggregates results into the summary table and
saves every failing case as a replayable file; :mod:`.command` is the ``pipeplug fuzz``
command. The checks and their tolerances are one table, :data:`.checks.CHECKS`.
"""
