"""pedalrepro: reproduction of Baines, "The influence of pedalling on the lateral dynamics of
cycling; a modelling approach" (TU Delft).

Physics and data code only: no Snakemake and no plotting side effects. Modules are named after
the thesis concepts (``legs``, ``disturbance``, ``linear``, ``response``, ...); see the README.
"""

__version__ = "0.1.0"

import os as _os

if _os.environ.get("PEDALREPRO_TRACE"):  # tests only: record the files a process reads
    from . import _trace

    _trace.install(_os.environ["PEDALREPRO_TRACE"])
