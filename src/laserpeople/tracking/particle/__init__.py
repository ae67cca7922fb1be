"""The particle-filter trackers of 004 (Schenk et al. 2011, Sec. 2): one filter per person,
all filters of a tracker in one array bank.

- :mod:`~laserpeople.tracking.particle.feet`: feet height, walking model (Sec. 2.1);
- :mod:`~laserpeople.tracking.particle.upper_body`: upper-body height, linear motion in
  Voronoi cells (Sec. 2.2);
- :mod:`~laserpeople.tracking.particle.bank` and
  :mod:`~laserpeople.tracking.particle.resampling`: the shared filter bank, systematic
  resampling and the effective sample size;
- :mod:`~laserpeople.tracking.particle.frames`: fused frames of several static lasers.
"""
