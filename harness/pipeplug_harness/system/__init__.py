"""``pipeplug system``: run a co-simulated system (SSP or OSP file) with libcosim, every
PipePlug and Hammer parameter checked first; write CSV and PNG.

* :mod:`.files`: read a system file as libcosim reads it;
* :mod:`.checks`: the checks before libcosim sees the file;
* :mod:`.run`: the libcosim run, every output of every component after each step;
* :mod:`.command`: the subcommand (CSV, PNG, summary).
"""
