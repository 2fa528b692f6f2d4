"""A target's depth from its levels: one package (DESIGN.md "Unknown target depth").

- `errors`: the levels' errors the depth likelihood integrates out, as the depth study measured
  them (on the one level likelihood, `tracker.levels`);
- `kstructure`: K averaged over the track's range uncertainty, and its spread there;
- `likelihood`: `TrackDepthLikelihood`, ln L of depth from every band along tracks, read from
  the tables;
- `posterior`: `DepthPosterior` under a prior uniform in ln(z + 1 m), its quantiles and the
  surface-or-submerged call;
- `bank`: depth hypotheses, each a tracker's run at that depth, weighed by the posterior along
  their tracks (the ML analysis's `tracker.mltma.depths` and the particle filters' bank).

The particle filter with the depth as a state was retired: its own depth interval covered the
truth in 7 % of the depth study's runs and its position error was 1.82x the filter given the
true depth, where the bank is 1.08x (docs/depth.md).
"""
