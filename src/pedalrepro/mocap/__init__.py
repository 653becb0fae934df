"""The treadmill motion-capture data of Moore, Kooijman and Schwab (Sec 4.1).

Moore, J. K.; Kooijman, J. D. G.; Schwab, A. L. (2014), "Motion Capture of Bicycling on a
Treadmill", figshare, DOI 10.6084/m9.figshare.1082512 (VU Amsterdam, January 2009; Optotrak
Certus, 31 markers, 100 Hz, 60 s runs).

Submodules, in the order the data flow through them:

- :mod:`~pedalrepro.mocap.fetch`: the pooch registry and download (``data/registry.txt``).
- :mod:`~pedalrepro.mocap.reader`: the per-run MATLAB files (``RNNN.mat``) -> :class:`Run`
  (metadata and marker trajectories in SI units, benchmark frame x forward, y right, z down).
- :mod:`~pedalrepro.mocap.kinematics`: rigid-body fits of the rear frame and the fork, then yaw,
  roll, steer (benchmark convention, Meijaard et al. 2007) and the crank angle.
- :mod:`~pedalrepro.mocap.cadence`: cadence from the right-foot marker's spectrum and the
  cadence-frequency amplitudes (Hann DFT of :mod:`pedalrepro.spectral`).
- :mod:`~pedalrepro.mocap.synthetic`: the synthetic stand-in, written in the published format.
- :mod:`~pedalrepro.mocap.runs`: the run index and the selection of the runs of Tables 4.1, 4.2.
"""

from .reader import MARKERS, MocapFileError, Run, read_run

__all__ = ["MARKERS", "MocapFileError", "Run", "read_run"]
