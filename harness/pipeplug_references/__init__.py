"""Independent references: exact and numerical solutions that never import the core they check.

* :mod:`pipeplug_references.closed_form`: model I under a rectangular pulse, in closed form;
* :mod:`pipeplug_references.rigid_ivp`: models I and II under piecewise-constant loads, each
  contact mode integrated by scipy's DOP853 with an event for every mode change;
* :mod:`pipeplug_references.rods`: elastic rods (model III): the free rod under any
  piecewise-constant end force (d'Alembert), and a rod with uniform dry friction under a constant
  end force, in closed form.
"""
