"""A rider-control layer: the Hess, Moore & Hubbard (2012) nested loops closed around the
thesis's linear models (beyond the thesis; its Sec 5 leaves a rider model to future work).

- :mod:`.plant`: the linear bicycle(-rider) of Eq 3.1 with heading and lateral position
  added, and the rider's second-order neuromuscular filter on the steer torque.
- :mod:`.gains`: the published gain rules (HumanControl ``generate_data.m``).
- :mod:`.closed_loop`: closed-loop eigenvalues and the closed-loop pedalling response.
- :mod:`.lean`: the hands-free lean-torque rider on Moore's leaning-rider plant, and why the
  gain rules give no stable loop on it.
"""
