"""Non-linear bicycle-rider models (thesis Sec 3.1.1.3, Fig 3.4): symbolic derivation with
SymBRiM/sympy (:mod:`.model`), cached generated code (:mod:`.codegen`), numeric evaluation and
linearisation (:mod:`.numeric`), parameter sets of the thesis models (:mod:`.parameters`), the
arm loops of model CF (:mod:`.arms`) and the linear-correction substitute HS
(:mod:`.substitute`)."""
