"""Hammer.fmu's ``documentation/index.html``, generated from the table the FMU registers.

The variable table comes from :mod:`pipeplug_fmu.blows`; only the equations and the timing
rules are text. Used by :mod:`pipeplug_fmu.build` at build time; not shipped in the FMU.
"""
from __future__ import annotations

from html import escape

from pipeplug import __version__

from . import blows, fmi
from .documentation import table

_EQUATIONS = """
<h2>Equations</h2>
<p>A train of <code>count</code> rectangular blows (<code>count = 0</code>: no end), blow k
(k = 0, 1, ...) starting at <code>start + k period</code>:</p>
<pre>
Q(t) = amplitude   if start + k period &lt;= t &lt; start + k period + duration
                   for some k &gt;= 0 (and k &lt; count when count &gt; 0)
Q(t) = 0           otherwise
</pre>
<p>With <code>ram_mass</code> &gt; 0 Hammer strikes with a ram instead (for PipePlug's own
ram, of the same mass): Q = 0, strike k (k = 0, 1, ...; k &lt; count when count &gt; 0) starts at
<code>start + 60 k / blows_per_minute</code>, the output <code>strikes</code> counts the strikes
started at or before t, and <code>v_strike = sqrt(2 efficiency rated_energy / ram_mass)</code>.
Connect <code>strikes</code> and <code>v_strike</code> to PipePlug's inputs of the same names:
each increase PipePlug sees at a communication point starts a strike there.</p>
<p>Q and strikes are right-continuous: at a blow edge it takes the value after the edge. A time within
1e-9 max(1, |t|) of an edge counts as on the edge, so hosts whose communication points are
k h, accumulated sums or integer nanoseconds (libcosim) land on the edges their grid
contains.</p>
"""

_TIMING = """
<h2>Output timing</h2>
<p>Q (and strikes) at the FMU's current time t is the value for the communication step that
starts at t:</p>
<ul>
<li>in initialization mode and after fmi2ExitInitializationMode: Q = Q(t_start), the start time
given to fmi2SetupExperiment (during initialization, from the parameter values set so far);</li>
<li>after fmi2DoStep(t, h): Q = Q(t + h), the force on [t + h, the next communication point).</li>
</ul>
<p>A host that steps Hammer and PipePlug together and passes Hammer's Q to PipePlug's input
after every step (as fixed-step masters such as libcosim do) hands PipePlug, for its step from
t, exactly Q(t): when the grid contains every blow edge, PipePlug is driven by the exact train,
with no one-step delay. A grid that misses an edge moves that edge to the next grid point.</p>
"""

_STATUSES = """
<h2>Stepping and statuses</h2>
<ul>
<li>The FMU keeps its own time: a doStep whose communication point differs from it by more than
1e-9 max(1, |t|) is refused (fmi2Discard); within that tolerance the FMU adopts the host's time.
A doStep of a step size that is not &gt; 0 is refused (fmi2Discard); the instance stays
usable. A doStep past the stopTime of fmi2SetupExperiment is fmi2Error, as FMI 2.0 requires.</li>
<li>A non-finite or out-of-range parameter makes fmi2ExitInitializationMode return fmi2Error; a
fixed parameter set after initialization, a get or set of an unknown value reference, a call out
of the FMI 2.0 call sequence (a doStep before initialization, ...), a NULL array or pointer and an
FMU state that is not one of this build are refused with fmi2Error. Each refusal is one log line
naming the variable (or the call), its value and the allowed range, logged whether debug logging
is on or off. After an fmi2Error the instance accepts fmi2SetFMUstate, fmi2Reset, fmi2Terminate
and fmi2FreeInstance; every other call is refused with one short line until fmi2Reset (or a
state set), which makes it usable again; other instances are not affected.</li>
<li>Every log line carries a category of the LogCategories in modelDescription.xml;
a <code>%</code> in logged text is written <code>%%</code>.</li>
<li>fmi2GetFMUstate, fmi2SetFMUstate and the serialization functions save the whole state
(time, stopTime, parameters, Q).</li>
</ul>
<h2>Host requirements</h2>
<p>As PipePlug.fmu: Hammer runs in a Python interpreter (with numpy, which the interpreter
search checks for). On linux64 its binary (<code>binaries/linux64/Hammer.so</code>, the same
loader as PipePlug's, in front of the pythonfmu binary <code>Hammer_pythonfmu.so</code>) uses a
Python already running in the host process, else the python executable named by the
environment variable <code>PIPEPLUG_PYTHON</code>, else <code>python3</code> on
<code>PATH</code>. On win64 the binary is pythonfmu's own, unchanged (refusals as fmi2Fatal); it
is not run-tested by this project. Hammer's modules have names of their own, so Hammer and
PipePlug run side by side in one interpreter.</p>
"""


def documentation_html(fmi_version: int = 2) -> str:
    """The whole ``index.html`` of Hammer.fmu of FMI ``fmi_version`` (2 or 3)."""
    parts = [f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
             f"<title>Hammer {__version__}</title></head><body>",
             f"<h1>Hammer {__version__}</h1>", f"<p>{escape(blows.DESCRIPTION)}."
             f" FMI {fmi_version}.0 co-simulation, model identifier <code>Hammer</code>.</p>",
             _EQUATIONS, _TIMING, "<h2>Variables</h2>", _output_table(), _parameter_table(),
             _STATUSES,
             *((fmi.fmi3_section("Hammer"),) if fmi_version == 3 else ()), "</body></html>\n"]
    return "\n".join(parts)


def _output_table() -> str:
    rows = [(name, kind, unit or "-", meaning) for name, kind, unit, meaning in blows.OUTPUTS]
    return table("Outputs (discrete, initial calculated)", ("name", "type", "unit", "meaning"),
                 rows)


def _parameter_table() -> str:
    rows = [(p.name, p.kind, p.unit or "-", f"{p.default:g}", p.allowed, p.description)
            for p in blows.PARAMETERS]
    return table("Parameters (fixed)", ("name", "type", "unit", "default", "allowed",
                                         "meaning"), rows)
