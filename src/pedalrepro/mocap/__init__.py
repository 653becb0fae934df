"""The treadmill motion-capture data of Moore, Kooijman and Schwab (Sec 4.1).

Moore, J. K.; Kooijman, J. D. G.; Schwab, A. L. (2014), "Motion Capture of Bicycling on a
Treadmill", figshare, DOI 10.6084/m9.figshare.1082512 (VU Amsterdam, January 2009; Optotrak
Certus, 31 markers, 100 Hz, 60 s runs).

Submodules, in the order the data flow through them:

- :mod:`~pedalrepro.mocap.fetch`: the pooch registries and downloads (``data/registry.txt``:
  figshare, file list from the DOI at run time; ``data/registry_public.txt``: the real public
  subset), data folder ``$PEDALREPRO_DATA_DIR``; resuming downloads, hash checks.
- :mod:`~pedalrepro.mocap.reader`: the per-run MATLAB files (``RNNN.mat``) -> :class:`Run`
  (metadata and marker trajectories in SI units, benchmark frame x forward, y right, z down).
- :mod:`~pedalrepro.mocap.exports`: per-coordinate exports (``RNNN_X.xlsx``, ``RNNNY.csv``)
  -> the same :class:`Run`, metadata from ``data/parameters/public_runs.yaml``.
- :mod:`~pedalrepro.mocap.kinematics`: rigid-body fits of the rear frame and the fork, then yaw,
  roll, steer (benchmark convention, Meijaard et al. 2007) and the crank angle.
- :mod:`~pedalrepro.mocap.cadence`: cadence from the right-foot marker's spectrum and the
  cadence-frequency amplitudes (Hann DFT of :mod:`pedalrepro.spectral`).
- :mod:`~pedalrepro.mocap.synthetic`: the synthetic stand-in, written in the published format.
- :mod:`~pedalrepro.mocap.runs`: the run index, the selection of the runs of Tables 4.1, 4.2,
  and :func:`~pedalrepro.mocap.runs.analyse_run` with its quality criteria (refuse, or analyse
  the usable part).
- :mod:`~pedalrepro.mocap.prepare`: the pipeline's run files per ``data_source`` (real where
  they can be had, labelled per row) and the extraction of all runs.
"""

from .reader import MARKERS, MocapFileError, Run, read_run

__all__ = ["MARKERS", "MocapFileError", "Run", "read_run"]
