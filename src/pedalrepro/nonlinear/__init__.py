"""Non-linear bicycle-rider models (thesis Sec 3.1.1.3, Fig 3.4).

Modules, leaves first (``tests/test_imports.py`` keeps the imports acyclic):

* :mod:`.symbolic` -- symbolic derivation with SymBRiM/sympy; :mod:`.codegen` -- its cached
  generated code; :mod:`.nonlinear_model` -- :class:`.nonlinear_model.NonlinearModel`, the
  numeric evaluation and linearisation of a parametrised model.
* :mod:`.rigid` -- rigid-body mass algebra (:class:`.rigid.RigidPart`); :mod:`.settings` --
  ``nonlinear_models.yaml``; :mod:`.bicycle_data` -- the one cached BicycleParameters/Yeadon
  load; :mod:`.prescribed` -- prescribed motion as Fourier series.
* :mod:`.arms` -- the arm loops of CF and HS (:mod:`.arm_design`: their parameters);
  :mod:`.leg_bodies` -- legs and cranks as bodies over a revolution; :mod:`.bodies` -- the
  benchmark parameters of each thesis model; :mod:`.models` -- the NT and NP models ready to
  integrate; :mod:`.sweep` -- NT/NP time solutions on the speed x cadence grid.
"""
