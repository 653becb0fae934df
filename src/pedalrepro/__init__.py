"""pedalrepro: reproduction of Baines, "The influence of pedalling on the lateral dynamics of
cycling; a modelling approach" (TU Delft).

Physics and data code only: no Snakemake and no plotting side effects. Modules are named after
the thesis concepts (``legs``, ``disturbance``, ``linear``, ``response``, ...); see the README.
"""

__version__ = "0.1.0"
